// bemsurg/solvers/bicgstab.hpp: BiCGStab (van der Vorst 1992), one of the three iterative
// re-solves after a cut in Wang et al. 2007 §5.3, Table 1. Right-preconditioned (x = M^-1 y), so
// the recurrence's residual is the unpreconditioned b - A x the caller's tolerance refers to.
//
// Breakdowns are named: rho = (r0~, r) (the shadow residual became orthogonal to r),
// sigma = (r0~, A M^-1 p), and omega = (t, s)/(t, t) (the stabilising minimal-residual step made no
// progress). When the recurrence's residual meets the tolerance the true residual is recomputed;
// if it does not, the residual is replaced by the true one and the recurrence restarts from it
// (counted in report().restarts); a restart that does not lower the true residual is stagnation.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "bemsurg/solvers/krylov_solver_base.hpp"
#include "bemsurg/solvers/linear_operator.hpp"

namespace bemsurg {

/// Solves A x = b through solve(b, x) (KrylovSolverBase). One iteration = one BiCGStab step =
/// two products with A.
/// \ingroup solvers
template <class Operator = DenseOperator, class Preconditioner = IdentityPreconditioner>
class BiCgStab : public KrylovSolverBase<BiCgStab<Operator, Preconditioner>, Operator, Preconditioner> {
  using Base = KrylovSolverBase<BiCgStab<Operator, Preconditioner>, Operator, Preconditioner>;
  // The workspace: r (s after the half step), the shadow r0~, p, v = A M^-1 p, M^-1 p, M^-1 s and
  // t = A M^-1 s (also the scratch for b - A x).
  Eigen::VectorXd r_, r0_, p_, v_, p_hat_, s_hat_, t_;

 public:
  using Base::Base;

 private:
  friend Base;  // solve() calls workspace(), iterate() and run_pass()

  Eigen::VectorXd& workspace(Eigen::Index n) {
    if (r_.size() != n) r_.resize(n), r0_.resize(n), p_.resize(n), v_.resize(n), p_hat_.resize(n), s_hat_.resize(n), t_.resize(n);
    return r_;
  }

  void iterate(const Operator& A, const Preconditioner& M, const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual,
               typename Base::Clock::time_point start) {
    this->iterate_with_replacement(A, M, b, x, residual, start, r_, t_);
  }

  /// One pass of the recurrence, from the residual in r_ with it as the shadow residual r0~.
  void run_pass(const Operator& A, const Preconditioner& M, Eigen::VectorXd& x, typename Base::Pass& pass) {
    const KrylovOptions& s = this->settings_;
    r0_ = r_;
    const double r0_norm = r0_.norm();
    double rho_old = 1.0, alpha = 1.0, omega = 1.0;
    v_.setZero();
    p_.setZero();
    while (this->report_.iterations < s.max_iterations) {
      const double r_norm = r_.norm();
      const double rho = r0_.dot(r_);
      if (this->stops(pass, rho, r0_norm * r_norm, "rho = (r0~, r)")) break;
      const double beta = (rho / rho_old) * (alpha / omega);
      p_ = r_ + beta * (p_ - omega * v_);
      M.apply(p_, p_hat_);
      A.apply(p_hat_, v_);
      const double sigma = r0_.dot(v_);
      if (this->stops(pass, sigma, r0_norm * v_.norm(), "sigma = (r0~, A M^-1 p)")) break;
      alpha = rho / sigma;
      r_ -= alpha * v_;  // r is now s = r - alpha v
      x += alpha * p_hat_;
      ++this->report_.iterations;
      const double s_norm = r_.norm();
      if (s_norm / this->b_norm_ <= s.tolerance) {  // half step already good enough
        this->record(s_norm);
        break;
      }
      M.apply(r_, s_hat_);
      A.apply(s_hat_, t_);
      const double tt = t_.squaredNorm(), ts = t_.dot(r_);
      if (!std::isfinite(tt) || !std::isfinite(ts)) {
        pass.stopped(KrylovStatus::NonFinite, "t = A M^-1 s");
        break;
      }
      if (this->vanished(ts, std::sqrt(tt) * s_norm)) {
        pass.stopped(KrylovStatus::Breakdown, "omega = (t, s) / (t, t)");
        this->record(s_norm);
        break;
      }
      omega = ts / tt;
      x += omega * s_hat_;
      r_ -= omega * t_;
      rho_old = rho;
      if (this->record(r_.norm()) <= s.tolerance) break;
    }
  }
};

}  // namespace bemsurg
