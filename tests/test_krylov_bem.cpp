// test_krylov_bem.cpp: GMRES, GMRES(m), BiCGStab and BiCG with each preconditioner on real BEM
// systems A* x = b (Wang et al. 2007 eq. 6; a soft block on its base under gravity): they reach the
// dense LU solution to the requested tolerance, a warm start from the solution before a local
// change (as after a cut, §5.3 / Table 1) takes fewer iterations than a cold one, and each
// preconditioner cuts the iteration count. Also the solve_linear_system dispatcher.
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <string>

#include "bemsurg/solvers/bicg.hpp"
#include "bemsurg/solvers/bicgstab.hpp"
#include "bemsurg/solvers/block_jacobi_preconditioner.hpp"
#include "bemsurg/solvers/gmres.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/solvers/near_field_preconditioner.hpp"
#include "support/krylov_test_systems.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;
using bemsurg_test::BemSystem;

namespace {

using bemsurg_test::kEps;

const BemSystem& base_system() {
  // 3 x 3 x 3 cells: 6 faces x 9 quads x 2 triangles = 108 elements, 3 unknowns each: 324 equations.
  static const BemSystem s = bemsurg_test::make_bem_system(3, 3, 3);
  return s;
}
const BemSystem& perturbed_system() {
  static const BemSystem s = bemsurg_test::make_bem_system(3, 3, 3, 0.04);
  return s;
}

double error_vs_lu(const BemSystem& s, const Eigen::VectorXd& x) { return (x - s.x_lu).norm() / s.x_lu.norm(); }

struct Run {
  KrylovStatus status;
  int iterations;
  double residual;
  double error;
};

template <template <class, class> class Solver, class Preconditioner>
Run solve_with(const BemSystem& s, const Preconditioner& M, KrylovOptions settings, Eigen::VectorXd x = Eigen::VectorXd()) {
  const DenseOperator op(s.A);
  Solver<DenseOperator, Preconditioner> solver(settings);
  const KrylovResult& r = solver.compute(op, M).solve(s.b, x);
  INFO(r.summary());
  CHECK(r.true_residual == Approx((s.b - s.A * x).norm() / s.b.norm()).epsilon(1e-6));
  return {r.status, r.iterations, r.true_residual, error_vs_lu(s, x)};
}

/// Runs one method with the three preconditioners at tolerance tol.
template <template <class, class> class Solver>
std::array<Run, 3> solve_all(const BemSystem& s, const KrylovOptions& settings) {
  const BlockJacobiPreconditioner jacobi(s.A);
  const NearFieldPreconditioner near(s.A, s.mesh, 1.5);
  return {solve_with<Solver>(s, IdentityPreconditioner(s.A.rows()), settings), solve_with<Solver>(s, jacobi, settings),
          solve_with<Solver>(s, near, settings)};
}

/// `error_bound`: ~3x the largest error reached at tolerance 1e-10 over the three preconditioners.
template <template <class, class> class Solver>
void check_method(const char* name, double error_bound, int restart = 0) {
  const BemSystem& s = base_system();
  KrylovOptions loose, tight;
  loose.tolerance = 1e-6;
  tight.tolerance = 1e-10;
  loose.max_iterations = tight.max_iterations = 3000;
  loose.restart = tight.restart = restart;
  const auto coarse = solve_all<Solver>(s, loose);
  const auto fine = solve_all<Solver>(s, tight);
  static const char* preconditioners[3] = {"none", "block_jacobi", "near_field"};
  for (int p = 0; p < 3; ++p) {
    INFO(name << " with preconditioner " << preconditioners[p] << ": " << coarse[p].iterations << " and " << fine[p].iterations
              << " iterations, errors " << coarse[p].error << " and " << fine[p].error);
    REQUIRE(fine[p].status == KrylovStatus::Converged);
    REQUIRE(coarse[p].status == KrylovStatus::Converged);
    CHECK(fine[p].residual <= tight.tolerance);
    // Error bound from the residual: ||x - x_LU|| / ||x_LU|| <= cond(A) * relative residual
    // (3.2e6 x 1e-10 = 3.2e-4), which holds for any iterate; the errors reached are far below it ...
    CHECK(fine[p].error <= s.lu_condition * tight.tolerance);
    // ... and the error follows the tolerance down (four decades of tolerance, at least two of error:
    // measured at least 2.4).
    CHECK(fine[p].error < 1e-2 * coarse[p].error);
    CHECK(fine[p].error < error_bound);
  }
  // Each preconditioner cuts the iteration count, and the near field more than the 3x3 blocks.
  CHECK(fine[1].iterations < fine[0].iterations);
  CHECK(fine[2].iterations < fine[1].iterations);
}

}  // namespace

TEST_CASE("the BEM test system is what the tests assume", "[krylov][bem]") {
  const BemSystem& s = base_system();
  CHECK(s.A.rows() == 324);
  // LU with partial pivoting is backward stable column by column: |b - A x| <= ~3 n eps |A| |x|
  // (entrywise; the unknowns mix displacements and tractions of very different size, so the
  // normwise |A| |x| would be 5.9e5 |b|). Measured 4.0e-16 |b|.
  CHECK((s.A * s.x_lu - s.b).norm() <= 3.0 * 324 * kEps * (s.A.cwiseAbs() * s.x_lu.cwiseAbs()).norm());
  CHECK(s.lu_condition > 1e6);  // hard enough that preconditioning shows (measured 3.2e6)
}

// Errors reached at tolerance 1e-10 (none, block-Jacobi, near field), iterations in brackets:
//   GMRES       4.5e-10 (185), 1.3e-10 (38), 1.8e-10 (17)
//   GMRES(40)   1.1e-9 (1916), 1.3e-10 (38), 1.8e-10 (17)
//   BiCGStab    6.0e-10 (2506), 1.8e-10 (26), 1.1e-10 (10)
//   BiCG        1.5e-10 (415), 1.2e-10 (40), 5.6e-11 (18)
TEST_CASE("full GMRES reaches the LU solution with each preconditioner", "[krylov][bem]") { check_method<Gmres>("GMRES", 1.4e-9); }
TEST_CASE("GMRES(40) reaches the LU solution with each preconditioner", "[krylov][bem]") { check_method<Gmres>("GMRES(40)", 3.3e-9, 40); }
TEST_CASE("BiCGStab reaches the LU solution with each preconditioner", "[krylov][bem]") { check_method<BiCgStab>("BiCGStab", 1.8e-9); }
TEST_CASE("BiCG reaches the LU solution with each preconditioner", "[krylov][bem]") { check_method<BiCg>("BiCG", 4.5e-10); }

TEST_CASE("a warm start from the solution before a local change takes fewer iterations", "[krylov][bem][warm]") {
  const BemSystem& before = base_system();
  const BemSystem& after = perturbed_system();
  const double change = error_vs_lu(after, before.x_lu);
  REQUIRE(change > 1e-4);  // the systems differ ...
  REQUIRE(change < 0.1);   // ... but not by much
  const BlockJacobiPreconditioner jacobi(after.A);
  KrylovOptions settings;
  settings.tolerance = 1e-8;
  const auto check = [&](const Run& cold, const Run& warm, const char* name) {
    INFO(name << ": cold " << cold.iterations << ", warm " << warm.iterations << " iterations");
    REQUIRE(cold.status == KrylovStatus::Converged);
    REQUIRE(warm.status == KrylovStatus::Converged);
    // cond(A) x tolerance = 3.2e-2; reached: 1.6e-8 (GMRES), 9.6e-9 (BiCGStab), 1.4e-8 (BiCG).
    CHECK(warm.error <= after.lu_condition * settings.tolerance);
    CHECK(warm.iterations < cold.iterations);
  };
  check(solve_with<Gmres>(after, jacobi, settings), solve_with<Gmres>(after, jacobi, settings, before.x_lu), "GMRES");
  check(solve_with<BiCgStab>(after, jacobi, settings), solve_with<BiCgStab>(after, jacobi, settings, before.x_lu), "BiCGStab");
  check(solve_with<BiCg>(after, jacobi, settings), solve_with<BiCg>(after, jacobi, settings, before.x_lu), "BiCG");
}

TEST_CASE("the near-field preconditioner keeps what it says and becomes exact at large radius", "[krylov][bem][near_field]") {
  const BemSystem& s = base_system();
  const Index E = s.mesh.num_elements();
  const auto built = std::chrono::steady_clock::now();
  const NearFieldPreconditioner small(s.A, s.mesh, 1.3);  // no centroid distance of this mesh lies at 1.3 diameters
  const double build_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count();
  const NearFieldStatistics& st = small.statistics();
  // Independent count of the pairs within radius x larger diameter.
  Index pairs = 0, ties = 0;
  for (Index i = 0; i < E; ++i)
    for (Index e = 0; e < E; ++e) {
      const double ratio = (s.mesh.centroid(i) - s.mesh.centroid(e)).norm() / std::max(s.mesh.diameter(i), s.mesh.diameter(e));
      pairs += (i == e || ratio < 1.3) ? 1 : 0;
      ties += std::abs(ratio - 1.3) < 1e-9 ? 1 : 0;
    }
  REQUIRE(ties == 0);
  CHECK(st.element_pairs == pairs);
  CHECK(st.nonzeros == 9 * pairs);
  CHECK(st.density == Approx(9.0 * pairs / double(s.A.size())));
  CHECK(st.fill >= 1.0 - 1e-12);
  // Timings: selection and factorisation are the build, which the constructor's wall time bounds.
  INFO("selection " << st.selection_seconds << " s, factor " << st.factor_seconds << " s, build " << st.build_seconds << " s, constructor "
                    << build_wall << " s");
  CHECK(st.selection_seconds > 0.0);
  CHECK(st.factor_seconds > 0.0);
  CHECK(st.build_seconds >= st.selection_seconds + st.factor_seconds - 1e-9);
  CHECK(st.build_seconds <= build_wall);
  // Radius larger than the body: M = A, so M^-1 b is the LU solution and GMRES needs one step.
  const NearFieldPreconditioner whole(s.A, s.mesh, 100.0);
  CHECK(whole.statistics().element_pairs == E * E);
  Eigen::VectorXd z(s.A.rows());
  whole.apply(s.b, z);
  // Measured 2.5e-15 and 5.7e-12 (transposed): the same matrix factored twice. Worst-case rounding
  // for two different solves would be cond(A) n eps = 2e-7; bounds 1e-9 kept.
  CHECK(error_vs_lu(s, z) < 1e-9);
  Eigen::VectorXd zt(s.A.rows()), lu_t = s.A.transpose().partialPivLu().solve(s.b);
  whole.apply_transpose(s.b, zt);
  CHECK((zt - lu_t).norm() < 1e-9 * lu_t.norm());
  KrylovOptions settings;
  settings.tolerance = 1e-10;
  CHECK(solve_with<Gmres>(s, whole, settings).iterations <= 2);
  // Bad input.
  CHECK_THROWS_WITH(NearFieldPreconditioner(s.A, s.mesh, 0.0), Catch::Contains("radius"));
  const Eigen::MatrixXd smaller = s.A.topLeftCorner(30, 30);
  CHECK_THROWS_WITH(NearFieldPreconditioner(smaller, s.mesh, 2.0), Catch::Contains("elements"));
}

TEST_CASE("block-Jacobi inverts the 3x3 diagonal blocks and names a singular one", "[krylov][bem]") {
  const BemSystem& s = base_system();
  const BlockJacobiPreconditioner M(s.A);
  Eigen::VectorXd z(s.A.rows()), zt(s.A.rows());
  M.apply(s.b, z);
  M.apply_transpose(s.b, zt);
  // A 3x3 solve through the column-equilibrated block (condition number <= 1.08 over every block
  // of this system, and no block mixes H and G columns): LU, inverse, scaling and the product each
  // cost a few eps. Measured 0.7 eps |b_e|; bound 32 eps.
  for (Index e = 0; e < s.mesh.num_elements(); e += 17) {
    const Eigen::Matrix3d block = s.A.block<3, 3>(3 * e, 3 * e);
    CHECK((block * z.segment<3>(3 * e) - s.b.segment<3>(3 * e)).norm() <= 32.0 * kEps * s.b.segment<3>(3 * e).norm() + 1e-300);
    CHECK((block.transpose() * zt.segment<3>(3 * e) - s.b.segment<3>(3 * e)).norm() <= 32.0 * kEps * s.b.segment<3>(3 * e).norm() + 1e-300);
  }
  Eigen::MatrixXd broken = s.A;
  broken.block<3, 3>(15, 15).setZero();
  CHECK_THROWS_WITH(BlockJacobiPreconditioner(broken), Catch::Contains("element 5"));
}

TEST_CASE("solve_linear_system dispatches to every method and reports", "[krylov][bem][dispatch]") {
  const BemSystem& s = base_system();
  for (const SolverMethod method : {SolverMethod::Lu, SolverMethod::Gmres, SolverMethod::BiCgStab, SolverMethod::BiCg})
    for (const PreconditionerKind preconditioner :
         {PreconditionerKind::None, PreconditionerKind::BlockJacobi, PreconditionerKind::NearField}) {
      LinearSolverOptions settings;
      settings.method = method;
      settings.preconditioner = preconditioner;
      settings.tolerance = 1e-10;
      settings.max_iterations = 3000;
      LinearSolveResult summary;
      const auto started = std::chrono::steady_clock::now();
      const Eigen::VectorXd x = solve_linear_system(s.A, s.b, settings, summary, &s.mesh);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      INFO(to_string(method) << " / " << to_string(preconditioner) << ": " << to_string(summary.status) << ", " << summary.iterations
                             << " iterations");
      CHECK(summary.method == method);
      // Setup (factorisation or preconditioner) and solve follow each other inside the call.
      CHECK(summary.solve_seconds > 0.0);
      CHECK(summary.setup_seconds + summary.solve_seconds <= wall);
      CHECK(summary.status == KrylovStatus::Converged);
      CHECK(summary.relative_residual == Approx((s.b - s.A * x).norm() / s.b.norm()).epsilon(1e-6));
      CHECK(summary.relative_residual <= (method == SolverMethod::Lu ? 1e-12 : settings.tolerance));
      // Reached: 0 (LU) and 4.2e-11 to 6.0e-10 (Krylov) against cond(A) x tolerance = 3.2e-4.
      CHECK(error_vs_lu(s, x) <= s.lu_condition * settings.tolerance);
      if (method == SolverMethod::Lu) {
        CHECK(summary.iterations == 0);
        break;  // the preconditioner does not apply to LU
      }
      CHECK(summary.iterations > 0);
      CHECK(summary.residual_history.size() >= 2);
      if (preconditioner == PreconditionerKind::NearField) {
        CHECK(summary.preconditioner_fill >= 1.0 - 1e-12);
        CHECK(summary.preconditioner_nonzeros > 0);
        CHECK(summary.setup_seconds > 0.0);
      }
    }
}

TEST_CASE("solve_linear_system throws on failure after filling the summary", "[krylov][dispatch]") {
  const BemSystem& s = base_system();
  LinearSolverOptions settings;
  settings.method = SolverMethod::Gmres;
  settings.max_iterations = 3;
  LinearSolveResult summary;
  CHECK_THROWS_WITH(solve_linear_system(s.A, s.b, settings, summary),
                    Catch::Contains("iteration_limit") && Catch::Contains("3 iterations") && Catch::Contains("residual"));
  CHECK(summary.status == KrylovStatus::IterationLimit);
  CHECK(summary.iterations == 3);
  CHECK(summary.relative_residual > settings.tolerance);

  settings.max_iterations = 100;
  // Names are parsed at the edges (scene files); an out-of-range enum value is still refused.
  CHECK_THROWS_WITH(parse_solver_method("cg"), Catch::Contains("unknown solver method 'cg'"));
  CHECK_THROWS_WITH(parse_preconditioner("ilu"), Catch::Contains("unknown preconditioner 'ilu'"));
  CHECK(parse_solver_method("bicgstab") == SolverMethod::BiCgStab);
  CHECK(parse_preconditioner("near_field") == PreconditionerKind::NearField);
  settings.method = static_cast<SolverMethod>(42);
  CHECK_THROWS_WITH(solve_linear_system(s.A, s.b, settings, summary), Catch::Contains("unknown solver method 42"));
  settings.method = SolverMethod::BiCg;
  settings.preconditioner = static_cast<PreconditionerKind>(7);
  CHECK_THROWS_WITH(solve_linear_system(s.A, s.b, settings, summary), Catch::Contains("unknown preconditioner value 7"));
  settings.preconditioner = PreconditionerKind::NearField;
  CHECK_THROWS_WITH(solve_linear_system(s.A, s.b, settings, summary), Catch::Contains("needs the mesh"));
  settings.preconditioner = PreconditionerKind::None;
  settings.restart = -1;
  CHECK_THROWS_WITH(solve_linear_system(s.A, s.b, settings, summary), Catch::Contains("restart"));
  settings.restart = 0;
  const Eigen::VectorXd wrong_guess = Eigen::VectorXd::Zero(5);
  CHECK_THROWS_WITH(solve_linear_system(s.A, s.b, settings, summary, nullptr, wrong_guess), Catch::Contains("initial guess"));

  LinearSolverOptions lu;
  Eigen::MatrixXd singular = s.A;
  singular.col(7).setZero();
  CHECK_THROWS_WITH(solve_linear_system(singular, s.b, lu, summary), Catch::Contains("singular"));
  CHECK(summary.status == KrylovStatus::Breakdown);
}
