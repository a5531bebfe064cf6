// linear_solve.cpp: the dispatcher behind solve_linear_system (include/bemsurg/solvers/linear_solve.hpp):
// "lu" by DenseLu, "gmres" / "bicgstab" / "bicg" by bemsurg's Krylov solvers with the preconditioner
// the scene names (Wang et al. 2007 eq. 6 for the system, §5.3 and Table 1 for the methods). Every
// path fills the summary before it returns or throws, so a failed solve is still reported.
#pragma once

#include "bemsurg/config.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/solvers/bicg.hpp"
#include "bemsurg/solvers/bicgstab.hpp"
#include "bemsurg/solvers/block_jacobi_preconditioner.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/gmres.hpp"
#include "bemsurg/solvers/identity_preconditioner.hpp"
#include "bemsurg/solvers/linear_operator.hpp"
#include "bemsurg/solvers/near_field_preconditioner.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {
namespace detail {

template <template <class, class> class Solver, class Preconditioner>
BEMSURG_INLINE Eigen::VectorXd run_krylov(const DenseOperator& A, const Preconditioner& M, const Eigen::VectorXd& b,
                                          const KrylovOptions& ks, const Eigen::VectorXd& x0, LinearSolveResult& summary) {
  Solver<DenseOperator, Preconditioner> solver(ks);
  solver.compute(A, M);
  Eigen::VectorXd x = x0;
  const KrylovResult& report = solver.solve(b, x);
  summary.status = report.status;
  summary.breakdown = report.breakdown;
  summary.iterations = report.iterations;
  summary.restarts = report.restarts;
  summary.initial_residual = report.initial_residual;
  summary.relative_residual = report.true_residual;
  summary.residual_history = report.residual_history;
  summary.solve_seconds = report.seconds;
  if (!report.converged())
    throw SolverError(std::string(to_string(summary.method)) + " (preconditioner " + to_string(summary.preconditioner) +
                      ") did not converge to relative residual " + scientific_text(ks.tolerance, 3) + ": " + report.summary());
  return x;
}

template <template <class, class> class Solver>
BEMSURG_INLINE Eigen::VectorXd run_with_preconditioner(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                                       const LinearSolverOptions& settings, const KrylovOptions& ks,
                                                       LinearSolveResult& summary, const TriangleMesh* mesh, const Eigen::VectorXd& x0) {
  const DenseOperator op(A);
  const auto setup_start = SteadyClock::now();
  if (settings.preconditioner == PreconditionerKind::None) {
    const IdentityPreconditioner M(A.rows());
    return run_krylov<Solver>(op, M, b, ks, x0, summary);
  }
  if (settings.preconditioner == PreconditionerKind::BlockJacobi) {
    const BlockJacobiPreconditioner M(A);
    summary.setup_seconds = seconds_since(setup_start);
    summary.preconditioner_nonzeros = 3 * A.rows();
    summary.preconditioner_fill = 1.0;
    return run_krylov<Solver>(op, M, b, ks, x0, summary);
  }
  if (settings.preconditioner == PreconditionerKind::NearField) {
#ifndef BEMSURG_HAVE_NEAR_FIELD
    (void)mesh;
    throw SolverError(
        "the near_field preconditioner is compiled into bemsurg::numerics, part of bemsurg::bemsurg (it needs SuiteSparse); "
        "this program uses the header-only core: link bemsurg::bemsurg or choose block_jacobi");
#else
    if (!mesh) throw SolverError("the near_field preconditioner needs the mesh (element centroids and diameters); none was given");
    const NearFieldPreconditioner M(A, *mesh, settings.near_field_radius);
    summary.setup_seconds = M.statistics().build_seconds;
    summary.preconditioner_nonzeros = M.statistics().nonzeros;
    summary.preconditioner_fill = M.statistics().fill;
    return run_krylov<Solver>(op, M, b, ks, x0, summary);
#endif
  }
  throw SolverError("solve_linear_system: unknown preconditioner value " + std::to_string(static_cast<int>(settings.preconditioner)));
}

/// Refuses a matrix or right-hand side with NaN or infinite entries before any solver sees it:
/// LAPACK's factorisation is undefined on them (it may crash) and a Krylov solve would spread
/// them into the result. Unknown k of A* is component k % 3 of element k / 3 (docs/design.md §2).
BEMSURG_INLINE void require_finite_system(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, LinearSolveResult& summary) {
  static const char* const likely =
      "; the likely cause is the material's Young's modulus (too small or too large: the Kelvin kernels divide by the "
      "shear modulus) or the mesh scale (coordinates far from metres overflow the kernels and the element areas)";
  Eigen::Index row = 0, col = 0;
  if (DenseLu::first_non_finite(A, row, col)) {
    summary.status = KrylovStatus::NonFinite;
    summary.breakdown = "non-finite system matrix";
    throw SolverError("the system matrix A* has a non-finite entry (" + number_text(A(row, col)) + " at row " + std::to_string(row) +
                      ", column " + std::to_string(col) + ": element " + std::to_string(row / 3) + ", unknown of element " +
                      std::to_string(col / 3) + ")" + likely);
  }
  for (Eigen::Index k = 0; k < b.size(); ++k)
    if (!std::isfinite(b(k))) {
      summary.status = KrylovStatus::NonFinite;
      summary.breakdown = "non-finite right-hand side";
      throw SolverError("the right-hand side has a non-finite entry (" + number_text(b(k)) + " at row " + std::to_string(k) + ": element " +
                        std::to_string(k / 3) + ", component " + "xyz"[k % 3] + "); check the prescribed values and gravity" + likely);
    }
}

BEMSURG_INLINE Eigen::VectorXd solve_lu(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, LinearSolveResult& summary) {
  const auto start = SteadyClock::now();
  const DenseLu lu(A);
  summary.setup_seconds = seconds_since(start);
  if (lu.info() != Eigen::Success) {
    summary.status = KrylovStatus::Breakdown;
    summary.breakdown = "LU pivot: the matrix is singular to working precision";
    throw SolverError("lu: the system matrix is singular to working precision (is the body supported?)");
  }
  const auto solve_start = SteadyClock::now();
  Eigen::VectorXd x = lu.solve(b);
  summary.solve_seconds = seconds_since(solve_start);
  const double b_norm = b.norm();
  const double residual = (b - A * x).norm();
  summary.relative_residual = b_norm > 0.0 ? residual / b_norm : residual;
  summary.initial_residual = 1.0;
  if (!std::isfinite(summary.relative_residual) || !x.allFinite()) {
    summary.status = KrylovStatus::NonFinite;
    summary.breakdown = "LU solution";
    throw SolverError("lu: the solution is not finite (NaN or infinity in the matrix or the right-hand side)");
  }
  summary.status = KrylovStatus::Converged;
  return x;
}

}  // namespace detail

BEMSURG_INLINE Eigen::VectorXd solve_linear_system(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const LinearSolverOptions& settings,
                                                   LinearSolveResult& summary, const TriangleMesh* mesh, const Eigen::VectorXd& x0) {
  summary = LinearSolveResult();
  summary.method = settings.method;
  summary.preconditioner = settings.method == SolverMethod::Lu ? PreconditionerKind::None : settings.preconditioner;
  summary.status = KrylovStatus::NotComputed;
  if (A.rows() != A.cols())
    throw SolverError("solve_linear_system: the matrix is " + std::to_string(A.rows()) + " x " + std::to_string(A.cols()) + ", not square");
  if (b.size() != A.rows())
    throw SolverError("solve_linear_system: the right-hand side has " + std::to_string(b.size()) + " entries, the matrix " +
                      std::to_string(A.rows()) + " rows");
  if (x0.size() != 0 && x0.size() != A.rows())
    throw SolverError("solve_linear_system: the initial guess has " + std::to_string(x0.size()) + " entries, the matrix " +
                      std::to_string(A.rows()) + " rows");
  detail::require_finite_system(A, b, summary);
  if (settings.method == SolverMethod::Lu) return detail::solve_lu(A, b, summary);

  KrylovOptions ks;
  ks.tolerance = settings.tolerance;
  ks.max_iterations = settings.max_iterations;
  ks.restart = settings.restart;
  ks.validate();
  switch (settings.method) {
    case SolverMethod::Gmres: return detail::run_with_preconditioner<Gmres>(A, b, settings, ks, summary, mesh, x0);
    case SolverMethod::BiCgStab: return detail::run_with_preconditioner<BiCgStab>(A, b, settings, ks, summary, mesh, x0);
    case SolverMethod::BiCg: return detail::run_with_preconditioner<BiCg>(A, b, settings, ks, summary, mesh, x0);
    case SolverMethod::Lu: break;
  }
  throw SolverError("solve_linear_system: unknown solver method " + std::to_string(static_cast<int>(settings.method)));
}

}  // namespace bemsurg
