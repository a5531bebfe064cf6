// Minimal bemsurg consumer: the numerical core as a user meets it, from headers alone.
//   1. a cube squeezed by uniform pressure, compared with the closed form u = -p (1 - 2 nu) x / E;
//   2. a soft block held at its bottom: the mesh validated, its Green's table computed, then cut
//      twice through the one cut entry point (CutSystemUpdate) with exact table updates, each
//      compared with a table computed from scratch on the cut mesh (recomputed_table_after).
// Exits non-zero if an answer is off, so packaging CI fails loudly rather than silently linking
// something broken. It includes only numerical-core headers, so the same file builds against
// bemsurg::bemsurg and against the header-only bemsurg::core (no compiled bemsurg library).
#include <algorithm>
#include <bemsurg/cutting/cut_system_update.hpp>
#include <bemsurg/cutting/table_update.hpp>
#include <bemsurg/elastostatics/elastostatic_problem.hpp>
#include <bemsurg/mesh/mesh_generators.hpp>
#include <bemsurg/mesh/mesh_validation.hpp>
#include <bemsurg/presolution/greens_table.hpp>
#include <bemsurg/verification/reference_solutions.hpp>
#include <bemsurg/version.hpp>
#include <iostream>
#include <memory>

namespace {

/// Largest difference of two matrices relative to the larger entry of the second.
double relative_max(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

/// A 6 x 6 x 2 cm block of soft tissue held at its bottom, sagging under gravity: validated, tabulated,
/// cut twice; the exact updates against tables from scratch. Returns the largest relative difference.
double cut_block_tables() {
  using namespace bemsurg;
  ElastostaticProblem block{box_mesh(Eigen::Vector3d(-0.03, -0.03, 0.0), Eigen::Vector3d(0.03, 0.03, 0.02), 6, 6, 2),
                            Material{3000.0, 0.45, 1000.0},
                            Eigen::Vector3d(0.0, 0.0, -9.81),
                            BoundaryConditions(),
                            {}};
  require_valid_mesh(block.mesh);  // names the bad face or edge if not
  block.boundary_conditions = BoundaryConditions(block.mesh.num_elements());
  for (Index e = 0; e < block.mesh.num_elements(); ++e)
    if (block.mesh.normal(e).z() < -0.99) block.boundary_conditions.prescribe_displacement(e, Eigen::Vector3d::Zero());
  auto table = std::make_shared<const GreensTable>(GreensTable::compute(block));  // every free element
  CutSystemUpdate system(table);
  double worst = 0.0;
  for (int step = 0; step < 2; ++step) {
    const std::shared_ptr<const GreensTable> before = system.table();
    const CutStepResult r = system.cut(Eigen::Vector3d(-0.01, 0.0, 0.02), Eigen::Vector3d::UnitX());
    if (!r.accepted) {
      std::cerr << "cut step " << step + 1 << " refused: " << r.reason << "\n";
      return 1.0;
    }
    system.wait_for_refactor();
    const std::shared_ptr<const GreensTable> exact = system.table();
    const std::shared_ptr<const GreensTable> reference = recomputed_table_after(*before, exact->mesh(), r.delta);
    worst = std::max({worst, relative_max(exact->columns(), reference->columns()),
                      relative_max(exact->base_displacement(), reference->base_displacement())});
    std::cout << "  cut step " << step + 1 << ": " << exact->num_elements() << " elements, " << r.delta.added.size()
              << " added, table against a fresh one " << worst << "\n";
  }
  return worst;
}

}  // namespace

int main() {
  using namespace bemsurg;
  const Material material{3000.0, 0.45, 1000.0};  // soft tissue: E = 3 kPa
  const TriangleMesh cube = box_mesh(Eigen::Vector3d(-0.01, -0.01, -0.01), Eigen::Vector3d(0.01, 0.01, 0.01), 3, 3, 3);
  const auto field = verification::uniform_pressure_field(material, 100.0);
  const auto errors = verification::solve_exact_trace_problem(cube, material, field, verification::a_few_elements(cube));
  std::cout << "bemsurg " << version_string() << ": cube under pressure, " << cube.num_elements()
            << " elements, relative displacement error " << errors.displacement << "\n";
  const double cut_difference = cut_block_tables();
  // The exact update equals a fresh factorisation to round-off (docs/cutting.md: about 1e-14).
  return errors.displacement < 0.1 && cut_difference < 1e-8 ? 0 : 1;
}
