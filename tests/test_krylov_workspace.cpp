// test_krylov_workspace.cpp: the Krylov iteration loops allocate nothing: once
// a solver object has solved a system of one size, solving it again (a new right-hand side or a
// warm start, as after each cut in Wang et al. 2007 §5.3) makes no heap allocation at all, with any
// preconditioner. Counted by tests/support/allocation_counter.hpp, which
// sees Eigen's aligned allocations, operator new and std::vector growth alike.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <thread>

#include "bemsurg/solvers/bicg.hpp"
#include "bemsurg/solvers/bicgstab.hpp"
#include "bemsurg/solvers/block_jacobi_preconditioner.hpp"
#include "bemsurg/solvers/gmres.hpp"
#include "bemsurg/solvers/near_field_preconditioner.hpp"
#include "support/allocation_counter.hpp"
#include "support/krylov_test_systems.hpp"

using namespace bemsurg;
using bemsurg_test::allocations_during;

namespace {

template <class Solver>
void check_second_solve_allocates_nothing(Solver& solver, const bemsurg_test::BemSystem& s) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(s.A.rows());
  REQUIRE(solver.solve(s.b, x).converged());  // sizes the workspace
  Eigen::VectorXd cold = Eigen::VectorXd::Zero(s.A.rows());
  Eigen::VectorXd warm = x + 1e-3 * s.x_lu;
  int iterations = 0;
  const long count = allocations_during([&] {
    iterations += solver.solve(s.b, cold).iterations;
    iterations += solver.solve(s.b, warm).iterations;
  });
  CHECK(solver.report().converged());
  CHECK(iterations > 2);
  CHECK(count == 0);
}

}  // namespace

TEST_CASE("the counter sees allocations", "[krylov][workspace]") {
  const long count = allocations_during([] {
    Eigen::VectorXd v(1000);
    v.setOnes();
    REQUIRE(v.sum() == 1000.0);
  });
  CHECK(count >= 1);
}

TEST_CASE("repeated solves allocate nothing", "[krylov][workspace]") {
  const bemsurg_test::BemSystem s = bemsurg_test::make_bem_system(2, 2, 2);
  const DenseOperator op(s.A);
  const BlockJacobiPreconditioner jacobi(s.A);
  const NearFieldPreconditioner near(s.A, s.mesh, 1.5);
  KrylovOptions settings;
  settings.tolerance = 1e-10;
  settings.max_iterations = 2000;
  SECTION("GMRES, no preconditioner") {
    Gmres<> solver(settings);
    solver.compute(op);
    check_second_solve_allocates_nothing(solver, s);
  }
  SECTION("GMRES(20), block-Jacobi") {
    settings.restart = 20;
    Gmres<DenseOperator, BlockJacobiPreconditioner> solver(settings);
    solver.compute(op, jacobi);
    check_second_solve_allocates_nothing(solver, s);
  }
  SECTION("BiCGStab, near field") {
    BiCgStab<DenseOperator, NearFieldPreconditioner> solver(settings);
    solver.compute(op, near);
    check_second_solve_allocates_nothing(solver, s);
  }
  SECTION("BiCG, near field") {
    BiCg<DenseOperator, NearFieldPreconditioner> solver(settings);
    solver.compute(op, near);
    check_second_solve_allocates_nothing(solver, s);
  }
}
