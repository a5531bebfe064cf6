// bemsurg/solvers/identity_preconditioner.hpp: "no preconditioner" (M = I) in the preconditioner
// concept the Krylov solvers take (Wang et al. 2007 §5.3 solve unpreconditioned).
//
// The preconditioner concept (a class used as `Preconditioner` by the solvers must provide):
//   Eigen::Index rows() const;
//   void apply(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const;            // z = M^-1 r
//   void apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const;  // z = M^-T r (BiCG)
// z never aliases r, and neither call may allocate.
#pragma once

#include <Eigen/Core>

namespace bemsurg {

/// "No preconditioner" (M = I) in the preconditioner concept the Krylov solvers take, described at the top of this
/// header: apply and apply_transpose copy r to z.
/// \ingroup solvers
class IdentityPreconditioner {
 public:
  IdentityPreconditioner() = default;
  explicit IdentityPreconditioner(Eigen::Index n) : n_(n) {}
  Eigen::Index rows() const { return n_; }
  void apply(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const { z = r; }
  void apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const { z = r; }

 private:
  Eigen::Index n_ = 0;
};

}  // namespace bemsurg
