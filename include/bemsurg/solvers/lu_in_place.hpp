// bemsurg/solvers/lu_in_place.hpp: one dense LU of A (overwritten by its factors) and the solve
// of many right-hand sides B (overwritten by the solutions), the step that dominates the Green's
// table precomputation (Wang et al. 2007 section 5.1). With BEMSURG_HAVE_BLAS this is LAPACK's
// dgetrf + dgetrs (threaded OpenBLAS, no copy of A); otherwise Eigen's PartialPivLU in place.
// Pivots are judged on the column-equilibrated matrix, as DenseLu does, so the singularity test
// does not depend on units. Throws SolverError when A is singular or has non-finite entries.
// LAPACKE's *_work entry points skip the NaN scans of A and B that the plain ones make on every
// call; finiteness of A is checked here before factorising (solvers/lu_factors.hpp says why).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/timing.hpp"
#include "bemsurg/types.hpp"

#ifdef BEMSURG_HAVE_BLAS
#include <lapacke.h>
#endif

namespace bemsurg {

/// Factorises A in place and overwrites B with A^-1 B; factor_seconds / solve_seconds (optional)
/// receive the two phases' wall times.
inline void lu_factor_and_solve_in_place(Eigen::MatrixXd& A, Eigen::MatrixXd& B, double* factor_seconds = nullptr,
                                         double* solve_seconds = nullptr) {
  const Index n = A.rows();
  if (A.cols() != n || B.rows() != n) throw SolverError("lu_factor_and_solve_in_place: sizes do not agree");
  if (n == 0) throw SolverError("lu_factor_and_solve_in_place: empty system");
  // Pivots are judged on the column-equilibrated matrix (scale-invariant; see DenseLu::compute).
  const Eigen::VectorXd column_max = DenseLu::column_maxima(A);
  if (!column_max.allFinite()) throw SolverError("the system matrix A* has non-finite entries");
  auto t0 = SteadyClock::now();
#ifdef BEMSURG_HAVE_BLAS
  std::vector<lapack_int> pivots(static_cast<std::size_t>(n));
  const lapack_int info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, lapack_int(n), lapack_int(n), A.data(), lapack_int(n), pivots.data());
  if (info < 0) throw SolverError("LAPACK dgetrf: invalid argument " + std::to_string(-info));
  if (info > 0 || !DenseLu::equilibrated_pivots_ok(A.diagonal(), column_max))
    throw SolverError("the system matrix A* is singular to working precision (is the body supported?)");
  if (factor_seconds) *factor_seconds = seconds_since(t0);
  t0 = SteadyClock::now();
  if (B.cols() > 0) {
    const lapack_int s = LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', lapack_int(n), lapack_int(B.cols()), A.data(), lapack_int(n),
                                             pivots.data(), B.data(), lapack_int(n));
    if (s != 0) throw SolverError("LAPACK dgetrs failed with info " + std::to_string(s));
  }
  if (solve_seconds) *solve_seconds = seconds_since(t0);
#else
  Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd> > lu(A);
  if (!DenseLu::equilibrated_pivots_ok(A.diagonal(), column_max))
    throw SolverError("the system matrix A* is singular to working precision (is the body supported?)");
  if (factor_seconds) *factor_seconds = seconds_since(t0);
  t0 = SteadyClock::now();
  if (B.cols() > 0) {
    Eigen::MatrixXd X = lu.solve(B);
    B.swap(X);
  }
  if (solve_seconds) *solve_seconds = seconds_since(t0);
#endif
}

}  // namespace bemsurg
