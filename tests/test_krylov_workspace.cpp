// test_krylov_workspace.cpp: the Krylov iteration loops allocate nothing (issue 4, item 5): once
// a solver object has solved a system of one size, solving it again (a new right-hand side or a
// warm start, as after each cut in Wang et al. 2007 §5.3) makes no heap allocation at all, with any
// preconditioner. Counted by wrapping malloc for this executable (glibc's __libc_malloc), which
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
#include "support/krylov_test_systems.hpp"

extern "C" void* __libc_malloc(std::size_t size);

namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
std::thread::id g_counted_thread;
}  // namespace

// Under AddressSanitizer malloc belongs to the sanitizer's allocator, so the counting wrapper is
// left out there (the count stays zero); the allocation check is made by the ordinary build.
#ifndef __SANITIZE_ADDRESS__
extern "C" void* malloc(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed) && std::this_thread::get_id() == g_counted_thread) ++g_allocations;
  return __libc_malloc(size);
}
#endif

using namespace bemsurg;

namespace {

/// Allocations made by this thread while f runs.
template <class F>
long allocations_during(F&& f) {
  g_counted_thread = std::this_thread::get_id();
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations.load();
}

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
  KrylovSettings settings;
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
