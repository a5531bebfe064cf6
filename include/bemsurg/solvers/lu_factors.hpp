// bemsurg/solvers/lu_factors.hpp: a dense LU factorisation that is kept (factors and pivots), so
// that later right-hand sides and low-rank updates after a cut reuse it (docs/design.md §7: the
// system grows by partitioning "on top of the factorisation kept from the precompute").
// With BEMSURG_HAVE_BLAS: LAPACK dgetrf / dgetrs (threaded OpenBLAS, no copy of A); otherwise
// Eigen's PartialPivLU in place. Memory: n^2 doubles for L and U (stored in A's storage) plus n
// pivots. The singularity test is DenseLu's (column-equilibrated pivots, scale-invariant).
// The LAPACKE *_work entry points: the plain ones scan the whole n x n matrix for NaN on every
// call (n^2 reads per solve, which at n in the thousands costs more than the solve of a few columns
// after a cut; benchmarks/bench_cut measures the solves); finiteness is checked once, before factorising, by column_maxima.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/system_factorization.hpp"
#include "bemsurg/timing.hpp"
#include "bemsurg/types.hpp"

#ifdef BEMSURG_HAVE_BLAS
#include <lapacke.h>
#endif

namespace bemsurg {

/// A dense LU factorisation that is kept (factors and pivots), so that later right-hand sides and low-rank updates after
/// a cut reuse it (docs/design.md §7). Takes over A's storage; the singularity test is DenseLu's.
/// \ingroup solvers
class LuFactors : public SystemFactorization {
 public:
  LuFactors() = default;

  /// Factorises A (taken over: its storage becomes the factors). Throws SolverError for a
  /// singular or non-finite A. `seconds` (optional) receives the factorisation's wall time.
  static LuFactors factor(Eigen::MatrixXd&& A, double* seconds = nullptr) {
    LuFactors f;
    const Index n = A.rows();
    if (A.cols() != n) throw SolverError("LuFactors: the matrix is not square");
    if (n == 0) throw SolverError("LuFactors: empty system");
    const Eigen::VectorXd column_max = DenseLu::column_maxima(A);
    if (!column_max.allFinite()) throw SolverError("the system matrix A* has non-finite entries");
    const auto t0 = SteadyClock::now();
    f.lu_.swap(A);
    f.pivots_.resize(static_cast<std::size_t>(n));
#ifdef BEMSURG_HAVE_BLAS
    std::vector<lapack_int> ipiv(static_cast<std::size_t>(n));
    const lapack_int info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, lapack_int(n), lapack_int(n), f.lu_.data(), lapack_int(n), ipiv.data());
    if (info < 0) throw SolverError("LAPACK dgetrf: invalid argument " + std::to_string(-info));
    for (std::size_t i = 0; i < ipiv.size(); ++i) f.pivots_[i] = static_cast<int>(ipiv[i]);  // 1-based row swaps
    const bool ok = info == 0;
#else
    Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd> > lu(f.lu_);
    for (Index i = 0; i < n; ++i) f.pivots_[static_cast<std::size_t>(i)] = lu.permutationP().indices()(i);  // P as indices
    const bool ok = true;
#endif
    if (!ok || !DenseLu::equilibrated_pivots_ok(f.lu_.diagonal(), column_max))
      throw SolverError("the system matrix A* is singular to working precision (is the body supported?)");
    if (seconds) *seconds = seconds_since(t0);
    return f;
  }

  Index size() const override { return lu_.rows(); }
  bool empty() const { return lu_.size() == 0; }
  /// Bytes held: n^2 doubles and n pivots.
  std::size_t bytes() const override { return static_cast<std::size_t>(lu_.size()) * sizeof(double) + pivots_.size() * sizeof(int); }
  const Eigen::MatrixXd& factors() const { return lu_; }

  /// A^-1, computed in the factors' own storage (LAPACK dgetri, 4/3 n^3 flops; without BLAS, Eigen
  /// solves the identity): the factorisation is used up (solvers/explicit_inverse.hpp).
  Eigen::MatrixXd inverse_in_place() && {
    const Index n = size();
    if (n == 0) throw SolverError("LuFactors::inverse_in_place: no factorisation");
#ifdef BEMSURG_HAVE_BLAS
    std::vector<lapack_int> ipiv(pivots_.begin(), pivots_.end());
    double query = 0.0;
    lapack_int info = LAPACKE_dgetri_work(LAPACK_COL_MAJOR, lapack_int(n), lu_.data(), lapack_int(n), ipiv.data(), &query, -1);
    if (info != 0) throw SolverError("LAPACK dgetri (workspace query) failed with info " + std::to_string(info));
    std::vector<double> work(static_cast<std::size_t>(std::max<double>(query, double(n))));
    info =
        LAPACKE_dgetri_work(LAPACK_COL_MAJOR, lapack_int(n), lu_.data(), lapack_int(n), ipiv.data(), work.data(), lapack_int(work.size()));
    if (info != 0) throw SolverError("LAPACK dgetri failed with info " + std::to_string(info) + " (A* singular)");
    pivots_.clear();
    return std::move(lu_);
#else
    Eigen::MatrixXd inv = Eigen::MatrixXd::Identity(n, n);
    solve_in_place(inv);
    lu_.resize(0, 0);
    pivots_.clear();
    return inv;
#endif
  }

  /// B <- A^-1 B (B has size() rows; any number of columns, solved together: BLAS-3).
  void solve_in_place(Eigen::Ref<Eigen::MatrixXd> B) const override {
    const Index n = size();
    if (B.rows() != n) throw SolverError("LuFactors::solve_in_place: " + std::to_string(B.rows()) + " rows, expected " + std::to_string(n));
    if (B.cols() == 0) return;
#ifdef BEMSURG_HAVE_BLAS
    std::vector<lapack_int> ipiv(pivots_.begin(), pivots_.end());
    const lapack_int s = LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', lapack_int(n), lapack_int(B.cols()), lu_.data(), lapack_int(n),
                                             ipiv.data(), B.data(), lapack_int(B.outerStride()));
    if (s != 0) throw SolverError("LAPACK dgetrs failed with info " + std::to_string(s));
#else
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> P(n);
    for (Index i = 0; i < n; ++i) P.indices()(i) = pivots_[static_cast<std::size_t>(i)];
    B = P * B;
    lu_.triangularView<Eigen::UnitLower>().solveInPlace(B);
    lu_.triangularView<Eigen::Upper>().solveInPlace(B);
#endif
  }

 private:
  Eigen::MatrixXd lu_;
  std::vector<int> pivots_;  // BLAS: LAPACK's 1-based row interchanges; Eigen: the permutation P's indices
};

}  // namespace bemsurg
