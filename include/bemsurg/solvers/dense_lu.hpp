// bemsurg/solvers/dense_lu.hpp: the direct solver, LU with partial pivoting of the dense A*.
// With BEMSURG_HAVE_BLAS Eigen routes the factorisation to LAPACK's dgetrf (OpenBLAS, threaded),
// about twice as fast on 2 cores (BUILD-NOTES.md). Shape as Eigen's solvers: compute, solve, info.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include "bemsurg/error.hpp"

namespace bemsurg {

class DenseLU {
 public:
  DenseLU() = default;
  explicit DenseLU(const Eigen::MatrixXd& A) { compute(A); }

  /// Factorises A. A numerically singular matrix (a zero or non-finite pivot) sets info() to
  /// NumericalIssue; solve() then throws instead of returning garbage.
  DenseLU& compute(const Eigen::MatrixXd& A) {
    if (A.rows() != A.cols()) throw SolverError("DenseLU: the matrix is not square");
    lu_.compute(A);
    const auto d = lu_.matrixLU().diagonal().cwiseAbs();
    const double largest = A.rows() ? A.cwiseAbs().maxCoeff() : 0.0;
    ok_ = A.rows() > 0 && d.allFinite() && d.minCoeff() > 1e-14 * largest;
    return *this;
  }

  Eigen::ComputationInfo info() const { return ok_ ? Eigen::Success : Eigen::NumericalIssue; }
  Eigen::Index rows() const { return lu_.rows(); }

  template <class Rhs>
  Eigen::Matrix<double, Eigen::Dynamic, Rhs::ColsAtCompileTime> solve(const Eigen::MatrixBase<Rhs>& b) const {
    if (!ok_) throw SolverError("DenseLU: the system matrix is singular to working precision (is the body supported?)");
    return lu_.solve(b);
  }

  /// Reciprocal condition number estimate (LAPACK-style, 1-norm): cheap health check for reports.
  double rcond() const { return lu_.rcond(); }

  const Eigen::PartialPivLU<Eigen::MatrixXd>& factorization() const { return lu_; }

 private:
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  bool ok_ = false;
};

}  // namespace bemsurg
