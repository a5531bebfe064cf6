// bemsurg/solvers/block_jacobi_preconditioner.hpp: M = the 3x3 diagonal blocks of A* (one block
// per constant element, docs/design.md §2). In the swapped BEM system (Wang et al. 2007 eq. 6) a column
// is H's (dimensionless, ~1/2 on the diagonal) or -G's (~ size / shear modulus), so the scales of
// the unknowns differ by orders of magnitude; inverting each element's own block undoes that and
// the self-coupling, at O(n) cost per application.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"

namespace bemsurg {

/// Block-Jacobi preconditioner M = the 3x3 diagonal blocks of A* (one block per constant element, docs/design.md §2):
/// inverting each element's own block undoes the differing scales of H and -G columns and the self-coupling, at O(n) per application.
/// \ingroup solvers
class BlockJacobiPreconditioner {
 public:
  BlockJacobiPreconditioner() = default;
  explicit BlockJacobiPreconditioner(const Eigen::MatrixXd& A) { compute(A); }

  /// Inverts every 3x3 diagonal block. Throws SolverError if A is not square with a size divisible
  /// by 3, or names the element whose block is singular or non-finite.
  BlockJacobiPreconditioner& compute(const Eigen::MatrixXd& A) {
    if (A.rows() != A.cols() || A.rows() % 3 != 0)
      throw SolverError("block-Jacobi preconditioner: the matrix is " + std::to_string(A.rows()) + " x " + std::to_string(A.cols()) +
                        "; it must be square with 3 unknowns per element");
    const Eigen::Index blocks = A.rows() / 3;
    inverses_.resize(3, A.rows());
    for (Eigen::Index e = 0; e < blocks; ++e) {
      const Eigen::Matrix3d block = A.block<3, 3>(3 * e, 3 * e);
      // Scale-invariant test: an element with mixed conditions has H columns (~1/2) and -G columns
      // (~ size / shear modulus) in one block, so each column is equilibrated to largest entry 1
      // first (block = S D^-1, block^-1 = D S^-1) and the pivots of S are judged against 1.
      const Eigen::Array3d column_max = block.cwiseAbs().colwise().maxCoeff().transpose().array();
      if (!block.allFinite() || !(column_max.minCoeff() > 0.0))
        throw SolverError("block-Jacobi preconditioner: the 3x3 diagonal block of element " + std::to_string(e) +
                          " is singular or non-finite");
      const Eigen::Vector3d d = column_max.inverse().matrix();
      const Eigen::Matrix3d scaled = block * d.asDiagonal();
      Eigen::FullPivLU<Eigen::Matrix3d> lu(scaled);
      if (!lu.isInvertible() || !(std::abs(lu.matrixLU()(2, 2)) > 1e-13))
        throw SolverError("block-Jacobi preconditioner: the 3x3 diagonal block of element " + std::to_string(e) +
                          " is singular or non-finite");
      inverses_.block<3, 3>(0, 3 * e) = d.asDiagonal() * lu.inverse();
    }
    return *this;
  }

  Eigen::Index rows() const { return inverses_.cols(); }
  /// The inverted blocks side by side: columns 3e..3e+2 hold block e's inverse.
  const Eigen::Matrix<double, 3, Eigen::Dynamic>& inverse_blocks() const { return inverses_; }

  void apply(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const {
    for (Eigen::Index k = 0; k < inverses_.cols(); k += 3) z.segment<3>(k).noalias() = inverses_.block<3, 3>(0, k) * r.segment<3>(k);
  }
  void apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const {
    for (Eigen::Index k = 0; k < inverses_.cols(); k += 3)
      z.segment<3>(k).noalias() = inverses_.block<3, 3>(0, k).transpose() * r.segment<3>(k);
  }

 private:
  Eigen::Matrix<double, 3, Eigen::Dynamic> inverses_;
};

}  // namespace bemsurg
