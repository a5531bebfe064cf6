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

template <class Operator = DenseOperator, class Preconditioner = IdentityPreconditioner>
class BiCgStab : public KrylovSolverBase<BiCgStab<Operator, Preconditioner>, Operator, Preconditioner> {
  using Base = KrylovSolverBase<BiCgStab<Operator, Preconditioner>, Operator, Preconditioner>;

 public:
  using Base::Base;

  /// Solves A x = b. On entry x is the initial guess (empty: zero), on exit the last iterate,
  /// whatever the status. One iteration = one BiCGStab step = two products with A.
  const KrylovReport& solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    typename Base::Clock::time_point start;
    if (!this->begin(b, x, start)) return this->report_;
    const KrylovSettings& s = this->settings_;
    const Operator& A = *this->A_;
    const Preconditioner& M = *this->M_;
    KrylovReport& report = this->report_;
    const Eigen::Index n = A.rows();
    if (r_.size() != n) r_.resize(n), r0_.resize(n), p_.resize(n), v_.resize(n), p_hat_.resize(n), s_hat_.resize(n), t_.resize(n);

    double residual = 0.0;
    if (!this->begin_residual(b, x, r_, residual, start)) return report;

    double replaced_at = residual;  // true residual when the recurrence last (re)started
    for (;;) {                      // one pass per (re)start of the recurrence from the true residual
      r0_ = r_;
      const double r0_norm = r0_.norm();
      double rho_old = 1.0, alpha = 1.0, omega = 1.0;
      v_.setZero();
      p_.setZero();
      const int started_at = report.iterations;
      const char* stop = nullptr;
      KrylovStatus status = KrylovStatus::NotComputed;
      while (report.iterations < s.max_iterations) {
        const double r_norm = r_.norm();
        const double rho = r0_.dot(r_);
        if (!std::isfinite(rho)) { status = KrylovStatus::NonFinite; stop = "rho = (r0~, r)"; break; }
        if (this->vanished(rho, r0_norm * r_norm)) { status = KrylovStatus::Breakdown; stop = "rho = (r0~, r)"; break; }
        const double beta = (rho / rho_old) * (alpha / omega);
        p_ = r_ + beta * (p_ - omega * v_);
        M.apply(p_, p_hat_);
        A.apply(p_hat_, v_);
        const double sigma = r0_.dot(v_);
        if (!std::isfinite(sigma)) { status = KrylovStatus::NonFinite; stop = "sigma = (r0~, A M^-1 p)"; break; }
        if (this->vanished(sigma, r0_norm * v_.norm())) {
          status = KrylovStatus::Breakdown;
          stop = "sigma = (r0~, A M^-1 p)";
          break;
        }
        alpha = rho / sigma;
        r_ -= alpha * v_;  // r is now s = r - alpha v
        x += alpha * p_hat_;
        ++report.iterations;
        const double s_norm = r_.norm();
        if (s_norm / this->b_norm_ <= s.tolerance) {  // half step already good enough
          record(s_norm);
          break;
        }
        M.apply(r_, s_hat_);
        A.apply(s_hat_, t_);
        const double tt = t_.squaredNorm(), ts = t_.dot(r_);
        if (!std::isfinite(tt) || !std::isfinite(ts)) { status = KrylovStatus::NonFinite; stop = "t = A M^-1 s"; break; }
        if (this->vanished(ts, std::sqrt(tt) * s_norm)) {
          status = KrylovStatus::Breakdown;
          stop = "omega = (t, s) / (t, t)";
          record(s_norm);
          break;
        }
        omega = ts / tt;
        x += omega * s_hat_;
        r_ -= omega * t_;
        rho_old = rho;
        if (record(r_.norm()) <= s.tolerance) break;
      }
      const double previous = replaced_at;
      Eigen::VectorXd& scratch = t_;
      report.true_residual = this->true_residual(b, x, scratch);
      if (!std::isfinite(report.true_residual)) return this->finish(KrylovStatus::NonFinite, stop ? stop : "solution update", start), report;
      if (report.true_residual <= s.tolerance) return this->finish(KrylovStatus::Converged, "", start), report;
      // A breakdown in the first step after a (re)start is final: restarting again would repeat it. Later ones
      // restart from the true residual with a fresh shadow vector (as Eigen's BiCGSTAB does for rho).
      if (status == KrylovStatus::NonFinite || (status == KrylovStatus::Breakdown && report.iterations <= started_at + 1))
        return this->finish(status, stop, start), report;
      if (report.iterations >= s.max_iterations) return this->finish(KrylovStatus::IterationLimit, "", start), report;
      // The recurrence claimed convergence that the true residual does not confirm (residual gap):
      // restart from the true residual, unless the last pass did not even lower it.
      if (status == KrylovStatus::NotComputed && report.true_residual > (1.0 - s.stagnation_reduction) * previous)
        return this->finish(KrylovStatus::Stagnation, "", start), report;
      r_ = scratch;
      replaced_at = report.true_residual;
      ++report.restarts;
    }
  }

 private:
  double record(double residual_norm) {
    const double relative = residual_norm / this->b_norm_;
    this->report_.estimated_residual = relative;
    this->report_.residual_history.push_back(relative);
    return relative;
  }

  Eigen::VectorXd r_, r0_, p_, v_, p_hat_, s_hat_, t_;
};

}  // namespace bemsurg
