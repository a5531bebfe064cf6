// Minimal bemsurg consumer: a cube squeezed by uniform pressure, compared with the closed form
// u = -p (1 - 2 nu) x / E. Exits non-zero if the answer is off, so packaging CI fails loudly
// rather than silently linking something broken. It includes only numerical-core headers, so the
// same file builds against bemsurg::bemsurg and against the header-only bemsurg::core.
#include <bemsurg/mesh/mesh_generators.hpp>
#include <bemsurg/verification/reference_solutions.hpp>
#include <bemsurg/version.hpp>
#include <iostream>

int main() {
  using namespace bemsurg;
  const Material material{3000.0, 0.45, 1000.0};  // soft tissue: E = 3 kPa
  const TriangleMesh cube = box_mesh(Eigen::Vector3d(-0.01, -0.01, -0.01), Eigen::Vector3d(0.01, 0.01, 0.01), 3, 3, 3);
  const auto field = verification::uniform_pressure_field(material, 100.0);
  const auto errors = verification::solve_exact_trace_problem(cube, material, field, verification::a_few_elements(cube));
  std::cout << "bemsurg " << version_string() << ": cube under pressure, " << cube.num_elements()
            << " elements, relative displacement error " << errors.displacement << "\n";
  return errors.displacement < 0.1 ? 0 : 1;
}
