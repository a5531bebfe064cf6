// bemsurg/solvers/linear_operator.hpp: what the Krylov solvers (GMRES, BiCGStab, BiCG; Wang et
// al. 2007 §5.3, Table 1) need from the system matrix A*, and the dense implementation of it.
//
// The operator concept (a class used as `Operator` by the solvers must provide):
//   Eigen::Index rows() const;                                        // square: n x n
//   void apply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y) const;            // y = A x
//   void apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y) const;  // y = A^T x
// y never aliases x, and neither call may allocate: the solvers call them every iteration.
// BiCG needs the transposed product; GMRES and BiCGStab never call it, so a matrix-free or
// compressed operator without a cheap transpose may define it to throw.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <string>
#include <utility>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bemsurg/error.hpp"

namespace bemsurg {

/// A* held as a dense Eigen matrix (not copied: the matrix must outlive the operator).
/// The product is Eigen's matrix-vector kernel, `noalias()` so no temporary is made; with
/// EIGEN_USE_BLAS (bemsurg's default when OpenBLAS is found) it is OpenBLAS's dgemv, which runs
/// on all cores. Without BLAS, Eigen's gemv is single-threaded and memory bound, so for large n the
/// rows are split across OpenMP threads (each thread streams its own part of A).
/// \ingroup solvers
class DenseOperator {
 public:
  explicit DenseOperator(const Eigen::MatrixXd& A) : A_(&A) {
    if (A.rows() != A.cols())
      throw SolverError("DenseOperator: the matrix is " + std::to_string(A.rows()) + " x " + std::to_string(A.cols()) + ", not square");
  }

  Eigen::Index rows() const { return A_->rows(); }
  Eigen::Index cols() const { return A_->cols(); }
  const Eigen::MatrixXd& matrix() const { return *A_; }

  void apply(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y) const {
#if !defined(EIGEN_USE_BLAS) && defined(_OPENMP)
    const Eigen::Index n = A_->rows();
    if (n >= kParallelThreshold) {
#pragma omp parallel
      {
        const auto [begin, size] = thread_range(n);
        if (size > 0) y.segment(begin, size).noalias() = A_->middleRows(begin, size) * x;
      }
      return;
    }
#endif
    y.noalias() = (*A_) * x;
  }

  void apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> y) const {
#if !defined(EIGEN_USE_BLAS) && defined(_OPENMP)
    const Eigen::Index n = A_->cols();
    if (n >= kParallelThreshold) {
#pragma omp parallel
      {
        const auto [begin, size] = thread_range(n);
        if (size > 0) y.segment(begin, size).noalias() = A_->middleCols(begin, size).transpose() * x;
      }
      return;
    }
#endif
    y.noalias() = A_->transpose() * x;
  }

 private:
#if !defined(EIGEN_USE_BLAS) && defined(_OPENMP)
  // Below this size a product takes a few microseconds and waking threads costs more than it saves.
  static constexpr Eigen::Index kParallelThreshold = 512;
  static std::pair<Eigen::Index, Eigen::Index> thread_range(Eigen::Index n);
#endif
  const Eigen::MatrixXd* A_;
};

#if !defined(EIGEN_USE_BLAS) && defined(_OPENMP)
inline std::pair<Eigen::Index, Eigen::Index> DenseOperator::thread_range(Eigen::Index n) {
  const Eigen::Index threads = omp_get_num_threads(), id = omp_get_thread_num();
  const Eigen::Index chunk = (n + threads - 1) / threads;
  const Eigen::Index begin = std::min(n, id * chunk);
  return {begin, std::min(chunk, n - begin)};
}
#endif

}  // namespace bemsurg
