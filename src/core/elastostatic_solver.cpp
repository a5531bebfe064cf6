// solve_elastostatic, the one-call facade, compiled once here under BEMSURG_SEPARATE_COMPILATION
// (include/bemsurg/config.hpp). It sits above assembly and solvers in the module order
// (docs/design.md, "Module order"), so it has a file of its own rather than sharing core's.
#include "bemsurg/elastostatic_solver.hpp"

#include "bemsurg/impl/elastostatic_solver_impl.hpp"

#include <Eigen/LU>
#include <chrono>
#include <mutex>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"

namespace bemsurg {

double estimate_elastostatic_seconds(Index num_elements) {
  static std::once_flag once;
  static double pair_seconds = 0.0, flop_seconds = 0.0;
  std::call_once(once, [] {
    using Clock = std::chrono::steady_clock;
    const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 2);  // 320 elements
    const InfluenceAssembler assembler(sphere, Material{});
    auto t0 = Clock::now();
    const InfluenceMatrices hg = assembler.assemble();
    const double E = double(sphere.num_elements());
    pair_seconds = std::chrono::duration<double>(Clock::now() - t0).count() / (E * E);
    t0 = Clock::now();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(hg.H);
    const double n = double(hg.H.rows());
    flop_seconds = std::chrono::duration<double>(Clock::now() - t0).count() / (2.0 / 3.0 * n * n * n);
  });
  const double E = double(num_elements), n = 3.0 * E;
  return pair_seconds * E * E + flop_seconds * 2.0 / 3.0 * n * n * n;
}

}  // namespace bemsurg
