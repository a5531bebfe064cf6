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

/// Solves A x = b through solve(b, x) (KrylovSolverBase). One iteration = one product with A
/// and one with A^T.
/// \ingroup solvers
template <class Operator = DenseOperator, class Preconditioner = IdentityPreconditioner>
class BiCg : public KrylovSolverBase<BiCg<Operator, Preconditioner>, Operator, Preconditioner> {
  using Base = KrylovSolverBase<BiCg<Operator, Preconditioner>, Operator, Preconditioner>;
  // The workspace: r, its shadow r~, z = M^-1 r, z~, the directions p, p~ and q = A p, q~ = A^T p~.
  Eigen::VectorXd r_, rt_, z_, zt_, p_, pt_, q_, qt_;

 public:
  using Base::Base;

 private:
  friend Base;  // solve() calls workspace(), iterate() and run_pass()

  Eigen::VectorXd& workspace(Eigen::Index n) {
    if (r_.size() != n) r_.resize(n), rt_.resize(n), z_.resize(n), zt_.resize(n), p_.resize(n), pt_.resize(n), q_.resize(n), qt_.resize(n);
    return r_;
  }

  void iterate(const Operator& A, const Preconditioner& M, const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual,
               typename Base::Clock::time_point start) {
    this->iterate_with_replacement(A, M, b, x, residual, start, r_, q_);  // q_: scratch for b - A x
  }

  /// One pass of the recurrence, from the residual in r_ with a fresh shadow residual.
  void run_pass(const Operator& A, const Preconditioner& M, Eigen::VectorXd& x, typename Base::Pass& pass) {
    rt_ = r_;
    double rho_old = 1.0;
    bool first = true;
    while (this->report_.iterations < this->settings_.max_iterations) {
      M.apply(r_, z_);
      M.apply_transpose(rt_, zt_);
      const double rho = z_.dot(rt_);
      if (this->stops(pass, rho, z_.norm() * rt_.norm(), "rho = (M^-1 r, r~)")) break;
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
      if (this->stops(pass, sigma, pt_.norm() * q_.norm(), "sigma = (p~, A p)")) break;
      const double alpha = rho / sigma;
      x += alpha * p_;
      r_ -= alpha * q_;
      rt_ -= alpha * qt_;
      rho_old = rho;
      ++this->report_.iterations;
      if (this->record(r_.norm()) <= this->settings_.tolerance) break;
    }
  }
};

}  // namespace bemsurg
