// bemsurg/solvers/dense_lu.hpp: the direct solver, LU with partial pivoting of the dense A*.
// With BEMSURG_HAVE_BLAS Eigen routes the factorisation to LAPACK's dgetrf (OpenBLAS, threaded),
// about twice as fast on 2 cores (docs/benchmarks.md). Shape as Eigen's solvers: compute, solve, info.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/LU>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

/// The direct solver of A* x = b: LU with partial pivoting of the dense matrix, with a scale-invariant singularity test
/// (column-equilibrated pivots). Shaped as Eigen's solvers: compute, solve, info.
/// \ingroup solvers
class DenseLu {
 public:
  DenseLu() = default;
  explicit DenseLu(const Eigen::MatrixXd& A) { compute(A); }

  /// Factorises A. A numerically singular matrix (a zero or non-finite pivot) sets info() to
  /// NumericalIssue; solve() then throws instead of returning garbage.
  ///
  /// The test is scale-invariant: A*'s columns are H's (~1/2) or -G's (~ size / shear modulus,
  /// 1e-15 for steel and millimetre elements), so pivots are judged on the column-equilibrated
  /// matrix A D, D = diag(1 / max_i |A_ij|): pivot j of A D is U_jj / max_i |A_ij|, and it must
  /// exceed 1e-14 (the equilibrated columns have largest entry 1). Partial pivoting chooses the
  /// same rows for A D as for A (scaling a column scales every candidate in it alike), and with
  /// power-of-two factors A D = L (U D) holds exactly, so factorising A itself and dividing its
  /// pivots by the column maxima is the equilibrated factorisation; solving for the scaled
  /// unknowns y = D^-1 x and unscaling gives the same x bit for bit, without an n x n copy.
  DenseLu& compute(const Eigen::MatrixXd& A) {
    if (A.rows() != A.cols()) throw SolverError("DenseLu: the matrix is not square");
    // LAPACK's dgetrf is not defined for NaN or infinite entries (OpenBLAS may crash in it):
    // refuse them before factorising. One O(n^2) pass against the O(n^3) factorisation.
    if (!A.allFinite()) {
      Eigen::Index row = 0, col = 0;
      first_non_finite(A, row, col);
      throw SolverError("DenseLu: the matrix has a non-finite entry (" + number_text(A(row, col)) + " at row " + std::to_string(row) +
                        ", column " + std::to_string(col) + "); it cannot be factorised");
    }
    const Eigen::VectorXd column_max = column_maxima(A);
    lu_.compute(A);
    ok_ = A.rows() > 0 && equilibrated_pivots_ok(lu_.matrixLU().diagonal(), column_max);
    return *this;
  }

  /// The first entry (column-major order) of A that is NaN or infinite; false when all are finite.
  static bool first_non_finite(const Eigen::Ref<const Eigen::MatrixXd>& A, Eigen::Index& row, Eigen::Index& col) {
    for (Eigen::Index j = 0; j < A.cols(); ++j)
      for (Eigen::Index i = 0; i < A.rows(); ++i)
        if (!std::isfinite(A(i, j))) {
          row = i;
          col = j;
          return true;
        }
    return false;
  }

  /// max_i |A_ij| per column j: the equilibration D = diag(1 / column_maxima(A)).
  static Eigen::VectorXd column_maxima(const Eigen::MatrixXd& A) { return A.cwiseAbs().colwise().maxCoeff().transpose(); }

  /// True when every pivot of the column-equilibrated factorisation, |U_jj| / column_max_j, is
  /// finite and above `tolerance`. `pivots` is the diagonal of U from A's own LU (partial
  /// pivoting), `column_max` the column maxima of A taken before it was factorised.
  static bool equilibrated_pivots_ok(const Eigen::Ref<const Eigen::VectorXd>& pivots, const Eigen::VectorXd& column_max,
                                     double tolerance = 1e-14) {
    if (pivots.size() != column_max.size() || column_max.size() == 0) return false;
    if (!column_max.allFinite() || !(column_max.minCoeff() > 0.0)) return false;  // a zero column is singular
    const Eigen::VectorXd scaled = pivots.cwiseAbs().cwiseQuotient(column_max);
    return scaled.allFinite() && scaled.minCoeff() > tolerance;
  }

  Eigen::ComputationInfo info() const { return ok_ ? Eigen::Success : Eigen::NumericalIssue; }
  Eigen::Index rows() const { return lu_.rows(); }

  template <class Rhs>
  Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime> solve(const Eigen::MatrixBase<Rhs>& b) const {
    if (!ok_) throw SolverError("DenseLu: the system matrix is singular to working precision (is the body supported?)");
    return lu_.solve(b);
  }

  /// Reciprocal condition number estimate (LAPACK-style, 1-norm) of A itself, not of the
  /// equilibrated matrix: cheap health check for reports.
  double rcond() const { return lu_.rcond(); }

  const Eigen::PartialPivLU<Eigen::MatrixXd>& factorization() const { return lu_; }

 private:
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  bool ok_ = false;
};

/// Deprecated name (before 0.2), kept one minor version: use DenseLu.

using DenseLU [[deprecated("renamed to DenseLu in bemsurg 0.2")]] = DenseLu;

}  // namespace bemsurg
