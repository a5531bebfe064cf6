// bemsurg/solvers/krylov_solver_base.hpp: what GMRES, BiCGStab and BiCG (Wang et al. 2007 §5.3,
// Table 1) share: the Eigen-like shape compute(A, M) / solve(b, x) / info(), the settings, the
// report of the last solve, input checks and the true-residual recomputation.
//
// The solver object is also the workspace: its vectors are sized on the first solve and reused, so
// repeated solves of the same size allocate nothing (the report's residual history keeps its
// capacity too). The operator and the preconditioner are held by pointer, as Eigen's iterative
// solvers hold the matrix: they must outlive the solver. One solver object per thread.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>

#include "bemsurg/error.hpp"
#include "bemsurg/solvers/identity_preconditioner.hpp"
#include "bemsurg/solvers/krylov_report.hpp"
#include "bemsurg/solvers/krylov_settings.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

/// CRTP base: Derived is the method (Gmres, BiCgStab, BiCg), so compute() returns it and calls
/// chain as with Eigen's solvers: `Gmres<> solver; solver.compute(A, M).solve(b, x)`.
template <class Derived, class Operator, class Preconditioner>
class KrylovSolverBase {
 public:
  KrylovSolverBase() = default;
  explicit KrylovSolverBase(const KrylovSettings& settings) : settings_(settings) {}

  /// Solves with operator A and preconditioner M (M approximates A; the solvers apply M^-1).
  Derived& compute(const Operator& A, const Preconditioner& M) { return set_operator(A, M), derived(); }
  /// Unpreconditioned (only when Preconditioner is IdentityPreconditioner).
  Derived& compute(const Operator& A) { return set_operator(A), derived(); }

  KrylovSettings& settings() { return settings_; }
  const KrylovSettings& settings() const { return settings_; }

  void set_operator(const Operator& A, const Preconditioner& M) {
    if (M.rows() != A.rows())
      throw SolverError("Krylov solver: the preconditioner has " + std::to_string(M.rows()) + " rows, the operator " +
                        std::to_string(A.rows()));
    A_ = &A;
    M_ = &M;
  }
  void set_operator(const Operator& A) {
    static_assert(std::is_same<Preconditioner, IdentityPreconditioner>::value,
                  "compute(A) without a preconditioner needs Preconditioner = IdentityPreconditioner");
    identity_ = IdentityPreconditioner(A.rows());
    set_operator(A, identity_);
  }

  const KrylovReport& report() const { return report_; }
  Eigen::ComputationInfo info() const { return report_.info(); }
  int iterations() const { return report_.iterations; }
  double error() const { return report_.true_residual; }

 protected:
  using Clock = SteadyClock;

  Derived& derived() { return static_cast<Derived&>(*this); }

  /// Checks sizes and settings, resets the report, cold-starts an empty x. Returns false (with the
  /// report already final) when there is nothing to iterate: non-finite input or b = 0.
  bool begin(const Eigen::VectorXd& b, Eigen::VectorXd& x, Clock::time_point& start) {
    start = Clock::now();
    if (!A_) throw SolverError("Krylov solver: solve() called before compute()");
    settings_.validate();
    const Eigen::Index n = A_->rows();
    if (b.size() != n)
      throw SolverError("Krylov solver: the right-hand side has " + std::to_string(b.size()) + " entries, the matrix " +
                        std::to_string(n) + " rows");
    if (x.size() == 0) x.setZero(n);
    if (x.size() != n)
      throw SolverError("Krylov solver: the initial guess has " + std::to_string(x.size()) + " entries, the matrix " +
                        std::to_string(n) + " rows");
    report_.status = KrylovStatus::NotComputed;
    report_.breakdown.clear();
    report_.iterations = 0;
    report_.restarts = 0;
    report_.initial_residual = report_.true_residual = report_.estimated_residual = 0.0;
    report_.residual_history.clear();
    // Reserve for typical solves only: a limit such as 1e8 must not cost 800 MB up front. Longer
    // runs grow the history past the cap (amortised; the capacity stays for later solves).
    report_.residual_history.reserve(
        static_cast<std::size_t>(std::min(settings_.max_iterations, kHistoryReserveCap)) + 2);
    report_.seconds = 0.0;
    b_norm_ = b.norm();
    if (!std::isfinite(b_norm_)) return finish(KrylovStatus::NonFinite, "right-hand side b", start), false;
    if (!x.allFinite()) return finish(KrylovStatus::NonFinite, "initial guess x0", start), false;
    if (b_norm_ == 0.0) {  // the exact solution of A x = 0 (A nonsingular) is x = 0
      x.setZero();
      report_.residual_history.push_back(0.0);
      return finish(KrylovStatus::Converged, "", start), false;
    }
    return true;
  }

  /// The opening every method shares once its workspace is sized: r = b - A x0 recorded as the
  /// initial residual. Returns false (with the report final) when x0 already solves the system or
  /// the residual is not finite; otherwise `residual` is ||r|| / ||b||.
  bool begin_residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r, double& residual,
                      Clock::time_point start) {
    residual = true_residual(b, x, r);
    report_.initial_residual = report_.true_residual = report_.estimated_residual = residual;
    report_.residual_history.push_back(residual);
    if (!std::isfinite(residual)) return finish(KrylovStatus::NonFinite, "initial residual b - A x0", start), false;
    if (residual <= settings_.tolerance) return finish(KrylovStatus::Converged, "", start), false;
    return true;
  }

  /// r = b - A x; returns ||r|| / ||b|| (NaN propagates).
  double true_residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r) const {
    A_->apply(x, r);
    r = b - r;
    return r.norm() / b_norm_;
  }

  void finish(KrylovStatus status, const char* quantity, Clock::time_point start) {
    report_.status = status;
    report_.breakdown = quantity;
    report_.seconds = seconds_since(start);
  }

  /// A scalar that is to be divided by has vanished: |value| <= tol * scale (or scale is zero).
  bool vanished(double value, double scale) const {
    return !(std::abs(value) > settings_.breakdown_tolerance * scale) || scale == 0.0;
  }

  /// Most iterations whose residual history is reserved before a solve (32 KiB).
  static constexpr int kHistoryReserveCap = 4096;

  KrylovSettings settings_;
  KrylovReport report_;
  const Operator* A_ = nullptr;
  const Preconditioner* M_ = nullptr;
  IdentityPreconditioner identity_;
  double b_norm_ = 0.0;
};

}  // namespace bemsurg
