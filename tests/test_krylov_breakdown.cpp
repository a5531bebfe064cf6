// test_krylov_breakdown.cpp: the Krylov solvers (GMRES, GMRES(m), BiCGStab, BiCG; Wang et al. 2007
// §5.3) never call a wrong answer converged. Crafted matrices that make each recurrence break
// down or stagnate must be reported as such, with the vanished quantity named; non-finite data,
// unattainable tolerances and bad input are reported, not returned as solutions.
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <chrono>
#include <limits>

#include "bemsurg/solvers/bicg.hpp"
#include "bemsurg/solvers/bicgstab.hpp"
#include "bemsurg/solvers/gmres.hpp"

using namespace bemsurg;

namespace {

double relative_residual(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  return (b - A * x).norm() / b.norm();
}

/// Well-conditioned nonsymmetric test matrix: identity plus a small random part (fixed seed).
Eigen::MatrixXd well_conditioned(int n) {
  std::srand(7);
  return Eigen::MatrixXd::Identity(n, n) + 0.3 / std::sqrt(double(n)) * Eigen::MatrixXd::Random(n, n);
}

/// Cyclic shift: A e_i = e_(i+1 mod n). With b = e_1 every Krylov space of dimension < n is
/// orthogonal to the residual's direction, so GMRES makes no progress before step n.
Eigen::MatrixXd cyclic_shift(int n) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) A((i + 1) % n, i) = 1.0;
  return A;
}

}  // namespace

TEST_CASE("each method converges on a well-conditioned system and reports the recomputed residual", "[krylov]") {
  const Eigen::MatrixXd A = well_conditioned(60);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(60, 1.0, 2.0);
  const Eigen::VectorXd exact = A.partialPivLu().solve(b);
  const DenseOperator op(A);
  KrylovOptions settings;
  settings.tolerance = 1e-12;
  const double condition = A.norm() * A.inverse().norm();

  // Solves, timing compute() + solve() with a clock around the call: the reported wall time of
  // the solve is positive and at most that (a report in ms or us, or of the wrong span, fails).
  auto timed = [](auto& solver, const DenseOperator& A, const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
    const auto start = std::chrono::steady_clock::now();
    solver.compute(A).solve(rhs, x);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    INFO("reported " << solver.report().seconds << " s, clock around the call " << wall << " s");
    CHECK(solver.report().seconds > 0.0);
    CHECK(solver.report().seconds <= wall);
    return solver.report();
  };
  auto check = [&](const KrylovResult& report, const Eigen::VectorXd& x) {
    CHECK(report.status == KrylovStatus::Converged);
    CHECK(report.info() == Eigen::Success);
    CHECK(report.true_residual <= settings.tolerance);
    CHECK(report.true_residual == Approx(relative_residual(A, b, x)).epsilon(1e-6));
    CHECK(report.initial_residual == Approx(1.0));  // cold start
    REQUIRE(report.residual_history.size() >= 2);
    CHECK(report.residual_history.front() == Approx(1.0));
    CHECK(report.iterations > 0);
    // cond(A) x tolerance = 6.2e-11; reached 3.1e-13 to 8.0e-13 (GMRES, GMRES(10), BiCGStab, BiCG).
    CHECK((x - exact).norm() / exact.norm() <= condition * settings.tolerance);
  };
  SECTION("full GMRES") {
    Gmres<> solver(settings);
    Eigen::VectorXd x;
    check(timed(solver, op, b, x), x);
    CHECK(solver.iterations() <= 60);  // n = 60 steps at most in exact arithmetic; measured 16
  }
  SECTION("GMRES(10)") {
    settings.restart = 10;
    Gmres<> solver(settings);
    Eigen::VectorXd x;
    check(timed(solver, op, b, x), x);
    CHECK(solver.report().restarts >= 1);
  }
  SECTION("BiCGStab") {
    BiCgStab<> solver(settings);
    Eigen::VectorXd x;
    check(timed(solver, op, b, x), x);
  }
  SECTION("BiCG") {
    BiCg<> solver(settings);
    Eigen::VectorXd x;
    check(timed(solver, op, b, x), x);
  }
}

TEST_CASE("BiCGStab breakdowns are reported with the vanished quantity", "[krylov][breakdown]") {
  SECTION("sigma = (r0~, A p) vanishes for a rotation by 90 degrees") {
    Eigen::Matrix2d A;
    A << 0.0, 1.0, -1.0, 0.0;  // (r, A r) = 0 for every r
    const Eigen::MatrixXd Ad = A;
    const DenseOperator op(Ad);
    BiCgStab<> solver;
    Eigen::VectorXd x;
    const KrylovResult& report = solver.compute(op).solve(Eigen::Vector2d(1.0, 0.0), x);
    CHECK(report.status == KrylovStatus::Breakdown);
    CHECK(report.breakdown.find("sigma") != std::string::npos);
    CHECK(report.true_residual == Approx(1.0));  // no progress, and it says so
    CHECK(solver.info() == Eigen::NumericalIssue);
  }
  SECTION("omega = (t, s)/(t, t) vanishes for diag(1, -1/4) and b = (1, 1/2)") {
    // First step: alpha = 4/3, s = (-1/3, 2/3), t = A s = (-1/3, -1/6), (t, s) = 1/9 - 1/9 = 0.
    Eigen::MatrixXd A = Eigen::Vector2d(1.0, -0.25).asDiagonal();
    const DenseOperator op(A);
    BiCgStab<> solver;
    Eigen::VectorXd x;
    const KrylovResult& report = solver.compute(op).solve(Eigen::Vector2d(1.0, 0.5), x);
    CHECK(report.status == KrylovStatus::Breakdown);
    CHECK(report.breakdown.find("omega") != std::string::npos);
    CHECK(report.true_residual > 0.1);
    CHECK(report.true_residual == Approx(relative_residual(A, Eigen::Vector2d(1.0, 0.5), x)));
  }
}

TEST_CASE("BiCG breakdown is reported with the vanished quantity", "[krylov][breakdown]") {
  Eigen::Matrix2d A;
  A << 0.0, 1.0, 1.0, 0.0;  // symmetric indefinite: (p, A p) = 0 for p = e1
  const Eigen::MatrixXd Ad = A;
  const DenseOperator op(Ad);
  BiCg<> solver;
  Eigen::VectorXd x;
  const KrylovResult& report = solver.compute(op).solve(Eigen::Vector2d(1.0, 0.0), x);
  CHECK(report.status == KrylovStatus::Breakdown);
  CHECK(report.breakdown.find("sigma") != std::string::npos);
  CHECK(report.true_residual == Approx(1.0));
}

TEST_CASE("GMRES(m) stagnation on a cyclic shift is reported, and full GMRES solves it in n steps", "[krylov][stagnation]") {
  const int n = 8;
  const Eigen::MatrixXd A = cyclic_shift(n);
  const Eigen::VectorXd b = Eigen::VectorXd::Unit(n, 0);
  const DenseOperator op(A);
  KrylovOptions settings;
  settings.restart = 3;
  Gmres<> restarted(settings);
  Eigen::VectorXd x;
  const KrylovResult& report = restarted.compute(op).solve(b, x);
  CHECK(report.status == KrylovStatus::Stagnation);
  CHECK(report.iterations == 3);  // one cycle without progress is enough to know
  CHECK(report.true_residual == Approx(1.0));
  CHECK(restarted.info() == Eigen::NoConvergence);

  settings.restart = 0;
  Gmres<> full(settings);
  Eigen::VectorXd y;
  const KrylovResult& full_report = full.compute(op).solve(b, y);
  CHECK(full_report.status == KrylovStatus::Converged);
  CHECK(full_report.iterations == n);
  // A^-1 = A^T for a permutation. Measured 0: Arnoldi on a permutation meets only unit vectors and
  // rotations by 90 degrees, exact in floating point; bound one rounding per step (|y| = 1).
  CHECK((y - A.transpose() * b).norm() <= n * std::numeric_limits<double>::epsilon());
}

TEST_CASE("GMRES on a singular system reports a breakdown, not a solution", "[krylov][breakdown]") {
  Eigen::MatrixXd A = Eigen::Vector3d(1.0, 2.0, 0.0).asDiagonal();
  const DenseOperator op(A);
  Gmres<> solver;
  Eigen::VectorXd x;
  const KrylovResult& report = solver.compute(op).solve(Eigen::Vector3d(1.0, 1.0, 1.0), x);
  CHECK(report.status == KrylovStatus::Breakdown);
  CHECK_FALSE(report.breakdown.empty());
  // The best any x can do: r = (1 - x1, 1 - 2 x2, 1) with x1 = 1, x2 = 1/2 up to rounding d, so
  // |r| = sqrt(1 + O(d^2)) and |r| / |b| = 1/sqrt(3) up to the sqrt and quotient's roundings (measured 0).
  CHECK(report.true_residual == Approx(1.0 / std::sqrt(3.0)).epsilon(4.0 * std::numeric_limits<double>::epsilon()));
}

TEST_CASE("an unattainable tolerance is never reported as converged", "[krylov]") {
  const Eigen::MatrixXd A = well_conditioned(40);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(40);
  const DenseOperator op(A);
  KrylovOptions settings;
  settings.tolerance = 1e-20;  // below double precision's reach for ||b - A x|| / ||b||
  settings.max_iterations = 400;
  Eigen::VectorXd x1, x2, x3;
  Gmres<> gmres(settings);
  BiCgStab<> bicgstab(settings);
  BiCg<> bicg(settings);
  for (const KrylovResult* report : {&gmres.compute(op).solve(b, x1), &bicgstab.compute(op).solve(b, x2), &bicg.compute(op).solve(b, x3)}) {
    CHECK_FALSE(report->converged());
    CHECK((report->status == KrylovStatus::Stagnation || report->status == KrylovStatus::IterationLimit ||
           report->status == KrylovStatus::Breakdown));
    CHECK(report->true_residual > settings.tolerance);
    // It got as far as double precision allows: measured 7.2e-17 to 1.4e-16. The attainable floor
    // for n = 40 and up to 400 iterations, ~(n + iterations) eps |A| |x| / |b|, is ~1e-12: kept.
    CHECK(report->true_residual < 1e-12);
  }
}

TEST_CASE("the iteration limit is reported with the residual reached", "[krylov]") {
  const Eigen::MatrixXd A = well_conditioned(50);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(50);
  const DenseOperator op(A);
  KrylovOptions settings;
  settings.max_iterations = 2;
  Gmres<> solver(settings);
  Eigen::VectorXd x;
  const KrylovResult& report = solver.compute(op).solve(b, x);
  CHECK(report.status == KrylovStatus::IterationLimit);
  CHECK(report.iterations == 2);
  CHECK(report.true_residual == Approx(relative_residual(A, b, x)));
  CHECK(report.true_residual > settings.tolerance);
  CHECK(report.summary().find("iteration_limit after 2 iterations") != std::string::npos);
}

TEST_CASE("non-finite values are reported as non_finite", "[krylov]") {
  Eigen::MatrixXd A = well_conditioned(10);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(10);
  SECTION("NaN in the matrix") {
    A(3, 4) = std::numeric_limits<double>::quiet_NaN();
    const DenseOperator op(A);
    Eigen::VectorXd x1, x2, x3;
    Gmres<> gmres;
    BiCgStab<> bicgstab;
    BiCg<> bicg;
    CHECK(gmres.compute(op).solve(b, x1).status == KrylovStatus::NonFinite);
    CHECK(bicgstab.compute(op).solve(b, x2).status == KrylovStatus::NonFinite);
    CHECK(bicg.compute(op).solve(b, x3).status == KrylovStatus::NonFinite);
  }
  SECTION("infinity in the right-hand side or the initial guess") {
    const DenseOperator op(A);
    Gmres<> gmres;
    Eigen::VectorXd bad_b = b, x;
    bad_b(2) = std::numeric_limits<double>::infinity();
    const KrylovResult& report = gmres.compute(op).solve(bad_b, x);
    CHECK(report.status == KrylovStatus::NonFinite);
    CHECK(report.breakdown.find("right-hand side") != std::string::npos);
    Eigen::VectorXd bad_x = Eigen::VectorXd::Zero(10);
    bad_x(0) = std::numeric_limits<double>::quiet_NaN();
    CHECK(gmres.solve(b, bad_x).breakdown.find("initial guess") != std::string::npos);
  }
}

TEST_CASE("b = 0 gives x = 0 at once, and a converged warm start takes no iteration", "[krylov]") {
  const Eigen::MatrixXd A = well_conditioned(20);
  const DenseOperator op(A);
  BiCg<> solver;
  solver.compute(op);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(20);
  CHECK(solver.solve(Eigen::VectorXd::Zero(20), x).converged());
  CHECK(x.isZero(0.0));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(20);
  Eigen::VectorXd exact = A.partialPivLu().solve(b);
  CHECK(solver.solve(b, exact).iterations == 0);
  CHECK(solver.report().converged());
}

TEST_CASE("bad input is rejected with a message naming it", "[krylov]") {
  const Eigen::MatrixXd A = well_conditioned(6);
  const DenseOperator op(A);
  Gmres<> solver;
  Eigen::VectorXd x;
  CHECK_THROWS_WITH(solver.solve(Eigen::VectorXd::Ones(6), x), Catch::Contains("before compute"));
  solver.compute(op);
  CHECK_THROWS_WITH(solver.solve(Eigen::VectorXd::Ones(5), x), Catch::Contains("right-hand side has 5 entries"));
  Eigen::VectorXd wrong = Eigen::VectorXd::Zero(4);
  CHECK_THROWS_WITH(solver.solve(Eigen::VectorXd::Ones(6), wrong), Catch::Contains("initial guess has 4 entries"));
  solver.settings().tolerance = -1.0;
  CHECK_THROWS_AS(solver.solve(Eigen::VectorXd::Ones(6), x), SolverError);
  solver.settings().tolerance = 1e-8;
  solver.settings().max_iterations = 0;
  CHECK_THROWS_WITH(solver.solve(Eigen::VectorXd::Ones(6), x), Catch::Contains("max_iterations"));
  const Eigen::MatrixXd rectangular(4, 5);
  CHECK_THROWS_WITH(DenseOperator(rectangular), Catch::Contains("not square"));
}
