// bemsurg/solvers/partitioned_inverse.hpp: inversion by partitioning, the paper's growth of a
// stored inverse by new rows and columns (Wang et al. 2007 §5.3, eqs. 11-13):
//   A = [[A0, Q], [P, S]],  with A0^-1 known:
//   S~ = (S - P A0^-1 Q)^-1,  P~ = -S~ (P A0^-1),  Q~ = -(A0^-1 Q) S~,
//   A^-1 = [[A0^-1 + (A0^-1 Q) S~ (P A0^-1), Q~], [P~, S~]].
// About 2 n^2 m flops for m new rows (n old). bemsurg's cut updates keep a factorisation rather than
// an explicit inverse (solvers/low_rank_updated_lu.hpp, the same algebra in factorised form); this
// explicit form is the paper's and the reference the factorised one is tested against.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include "bemsurg/error.hpp"

namespace bemsurg {

inline Eigen::MatrixXd grow_inverse_by_partitioning(const Eigen::MatrixXd& A0_inverse, const Eigen::MatrixXd& P, const Eigen::MatrixXd& Q,
                                                    const Eigen::MatrixXd& S) {
  const Eigen::Index n = A0_inverse.rows(), m = S.rows();
  if (A0_inverse.cols() != n || P.rows() != m || P.cols() != n || Q.rows() != n || Q.cols() != m || S.cols() != m)
    throw InvalidArgumentError("grow_inverse_by_partitioning: blocks of inconsistent sizes");
  const Eigen::MatrixXd AQ = A0_inverse * Q;  // A0^-1 Q   (n x m)
  const Eigen::MatrixXd PA = P * A0_inverse;  // P A0^-1   (m x n)
  Eigen::PartialPivLU<Eigen::MatrixXd> schur((S - P * AQ).eval());
  if (!(schur.rcond() > 1e-15)) throw SolverError("grow_inverse_by_partitioning: the Schur complement S - P A0^-1 Q is singular");
  const Eigen::MatrixXd St = schur.inverse();  // eq. 11
  Eigen::MatrixXd out(n + m, n + m);
  out.bottomRightCorner(m, m) = St;
  out.bottomLeftCorner(m, n).noalias() = -St * PA;  // eq. 12
  out.topRightCorner(n, m).noalias() = -AQ * St;    // eq. 12
  out.topLeftCorner(n, n) = A0_inverse;
  out.topLeftCorner(n, n).noalias() += AQ * (St * PA);  // eq. 13
  return out;
}

}  // namespace bemsurg
