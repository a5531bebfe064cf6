// bemsurg/solvers/bicg.hpp: the biconjugate gradient method (Fletcher 1976), the third iterative
// re-solve after a cut in Wang et al. 2007 §5.3, Table 1. It runs a second, "shadow" recurrence
// with A^T, so it needs the operator's apply_transpose (and the preconditioner's).
//
// Preconditioned as in Barrett et al., Templates (1994), Fig. 2.7: z = M^-1 r, z~ = M^-T r~; the
// recurrence's r is the unpreconditioned residual b - A x. Breakdowns are named: rho = (z, r~) (the
// two residual sequences became orthogonal) and sigma = (p~, A p) (the two search directions did).
// Convergence claimed by the recurrence is confirmed on the recomputed residual; if that fails the
// residual is replaced by the true one and the recurrence restarts (report().restarts); a restart
// that does not lower the true residual is stagnation.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "bemsurg/solvers/krylov_solver_base.hpp"
#include "bemsurg/solvers/linear_operator.hpp"

namespace bemsurg {

template <class Operator = DenseOperator, class Preconditioner = IdentityPreconditioner>
class BiCg : public KrylovSolverBase<BiCg<Operator, Preconditioner>, Operator, Preconditioner> {
  using Base = KrylovSolverBase<BiCg<Operator, Preconditioner>, Operator, Preconditioner>;

 public:
  using Base::Base;

  /// Solves A x = b. On entry x is the initial guess (empty: zero), on exit the last iterate,
  /// whatever the status. One iteration = one product with A and one with A^T.
  const KrylovReport& solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    typename Base::Clock::time_point start;
    if (!this->begin(b, x, start)) return this->report_;
    const KrylovSettings& s = this->settings_;
    const Operator& A = *this->A_;
    const Preconditioner& M = *this->M_;
    KrylovReport& report = this->report_;
    const Eigen::Index n = A.rows();
    if (r_.size() != n)
      r_.resize(n), rt_.resize(n), z_.resize(n), zt_.resize(n), p_.resize(n), pt_.resize(n), q_.resize(n), qt_.resize(n);

    double residual = 0.0;
    if (!this->begin_residual(b, x, r_, residual, start)) return report;

    double replaced_at = residual;
    for (;;) {  // one pass per (re)start of the recurrence from the true residual
      rt_ = r_;
      double rho_old = 1.0;
      bool first = true;
      const int started_at = report.iterations;
      const char* stop = nullptr;
      KrylovStatus status = KrylovStatus::NotComputed;
      while (report.iterations < s.max_iterations) {
        M.apply(r_, z_);
        M.apply_transpose(rt_, zt_);
        const double rho = z_.dot(rt_);
        if (!std::isfinite(rho)) { status = KrylovStatus::NonFinite; stop = "rho = (M^-1 r, r~)"; break; }
        if (this->vanished(rho, z_.norm() * rt_.norm())) { status = KrylovStatus::Breakdown; stop = "rho = (M^-1 r, r~)"; break; }
        if (first) {
          p_ = z_;
          pt_ = zt_;
          first = false;
        } else {
          const double beta = rho / rho_old;
          p_ = z_ + beta * p_;
          pt_ = zt_ + beta * pt_;
        }
        A.apply(p_, q_);
        A.apply_transpose(pt_, qt_);
        const double sigma = pt_.dot(q_);
        if (!std::isfinite(sigma)) { status = KrylovStatus::NonFinite; stop = "sigma = (p~, A p)"; break; }
        if (this->vanished(sigma, pt_.norm() * q_.norm())) { status = KrylovStatus::Breakdown; stop = "sigma = (p~, A p)"; break; }
        const double alpha = rho / sigma;
        x += alpha * p_;
        r_ -= alpha * q_;
        rt_ -= alpha * qt_;
        rho_old = rho;
        ++report.iterations;
        const double relative = r_.norm() / this->b_norm_;
        report.estimated_residual = relative;
        report.residual_history.push_back(relative);
        if (relative <= s.tolerance) break;
      }
      const double previous = replaced_at;
      report.true_residual = this->true_residual(b, x, q_);
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
      r_ = q_;
      replaced_at = report.true_residual;
      ++report.restarts;
    }
  }

 private:
  Eigen::VectorXd r_, rt_, z_, zt_, p_, pt_, q_, qt_;
};

}  // namespace bemsurg
