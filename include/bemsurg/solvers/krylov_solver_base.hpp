// bemsurg/solvers/krylov_solver_base.hpp: what GMRES, BiCGStab and BiCG (Wang et al. 2007 §5.3,
// Table 1) share: the Eigen-like shape compute(A, M) / solve(b, x) / info(), the settings, the
// report of the last solve, input checks and the true-residual recomputation.
//
// The solver object is also the workspace: its vectors are sized on the first solve and reused, so
// repeated solves of the same size allocate nothing (the report's residual history keeps its
// capacity too). The operator and the preconditioner are held by pointer, as Eigen's iterative
// solvers hold the matrix: they must outlive the solver. One solver object per thread.
//
// As in Eigen's IterativeLinearSolvers, solve() lives here and opens every solve the same way
// (checks, b = 0, workspace, initial residual r = b - A x0); the method adds only its iteration:
//
//   DenseOperator A(matrix);                      // or any operator with rows() and apply()
//   BlockJacobiPreconditioner M(matrix);
//   Gmres<DenseOperator, BlockJacobiPreconditioner> gmres;   // or BiCgStab<...>, BiCg<...>
//   gmres.settings().tolerance = 1e-8;
//   Eigen::VectorXd x;                            // empty: start from zero
//   const KrylovResult& report = gmres.compute(A, M).solve(b, x);
//   if (!report.converged()) throw SolverError(report.summary());
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>

#include "bemsurg/error.hpp"
#include "bemsurg/solvers/identity_preconditioner.hpp"
#include "bemsurg/solvers/krylov_options.hpp"
#include "bemsurg/solvers/krylov_result.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

/// CRTP base: Derived is the method (Gmres, BiCgStab, BiCg), so compute() returns it and calls
/// chain as with Eigen's solvers: `Gmres<> solver; solver.compute(A, M).solve(b, x)`. Derived
/// provides `Eigen::VectorXd& workspace(n)` (sizes its vectors when n changed, returns the one
/// that holds the residual) and `void iterate(A, M, b, x, residual, start)` (from x0, whose
/// relative residual `residual` is in that vector, until it calls finish()).
/// \ingroup solvers
template <class Derived, class Operator, class Preconditioner>
class KrylovSolverBase {
 public:
  KrylovSolverBase() = default;
  explicit KrylovSolverBase(const KrylovOptions& settings) : settings_(settings) {}

  /// Solves A x = b. On entry x is the initial guess (empty: zero), on exit the last iterate,
  /// whatever the status. Returns the report (also report()).
  const KrylovResult& solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    Clock::time_point start;
    if (!begin(b, x, start)) return report_;
    Eigen::VectorXd& r = derived().workspace(A_->rows());
    double residual = 0.0;
    if (!begin_residual(b, x, r, residual, start)) return report_;
    derived().iterate(*A_, *M_, b, x, residual, start);
    return report_;
  }

  /// Solves with operator A and preconditioner M (M approximates A; the solvers apply M^-1).
  Derived& compute(const Operator& A, const Preconditioner& M) { return set_operator(A, M), derived(); }
  /// Unpreconditioned (only when Preconditioner is IdentityPreconditioner).
  Derived& compute(const Operator& A) { return set_operator(A), derived(); }

  KrylovOptions& settings() { return settings_; }
  const KrylovOptions& settings() const { return settings_; }

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

  const KrylovResult& report() const { return report_; }
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
      throw SolverError("Krylov solver: the right-hand side has " + std::to_string(b.size()) + " entries, the matrix " + std::to_string(n) +
                        " rows");
    if (x.size() == 0) x.setZero(n);
    if (x.size() != n)
      throw SolverError("Krylov solver: the initial guess has " + std::to_string(x.size()) + " entries, the matrix " + std::to_string(n) +
                        " rows");
    report_.status = KrylovStatus::NotComputed;
    report_.breakdown.clear();
    report_.iterations = 0;
    report_.restarts = 0;
    report_.initial_residual = report_.true_residual = report_.estimated_residual = 0.0;
    report_.residual_history.clear();
    // Reserve for typical solves only: a limit such as 1e8 must not cost 800 MB up front. Longer
    // runs grow the history past the cap (amortised; the capacity stays for later solves).
    report_.residual_history.reserve(static_cast<std::size_t>(std::min(settings_.max_iterations, kHistoryReserveCap)) + 2);
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
  bool begin_residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r, double& residual, Clock::time_point start) {
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

  /// Records the recurrence's residual estimate ||r|| (absolute); returns it relative to ||b||.
  double record(double residual_norm) {
    const double relative = residual_norm / b_norm_;
    report_.estimated_residual = relative;
    report_.residual_history.push_back(relative);
    return relative;
  }

  /// A scalar that is to be divided by has vanished: |value| <= tol * scale (or scale is zero).
  bool vanished(double value, double scale) const { return !(std::abs(value) > settings_.breakdown_tolerance * scale) || scale == 0.0; }

  /// One pass of a recurrence that replaces its residual by the true one (BiCG, BiCGStab): from
  /// a (re)start to the iteration that stopped it.
  struct Pass {
    int started_at = 0;                               // report().iterations at the (re)start
    KrylovStatus status = KrylovStatus::NotComputed;  // NonFinite or Breakdown: a scalar stopped it
    const char* stop = nullptr;                       // ... and which one
    bool stopped(KrylovStatus why, const char* quantity) {
      status = why;
      stop = quantity;
      return true;
    }
  };

  /// True (the pass stopped, the quantity named) when a scalar the recurrence divides by is not
  /// finite or has vanished against `scale` (see vanished()).
  bool stops(Pass& pass, double value, double scale, const char* quantity) const {
    if (!std::isfinite(value)) return pass.stopped(KrylovStatus::NonFinite, quantity);
    if (vanished(value, scale)) return pass.stopped(KrylovStatus::Breakdown, quantity);
    return false;
  }

  /// The outer loop of BiCG and BiCGStab: passes of the recurrence (Derived::run_pass(A, M, x,
  /// pass)) on the residual in `r`, each ended by restart_from_true_residual() with `scratch`.
  void iterate_with_replacement(const Operator& A, const Preconditioner& M, const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual,
                                Clock::time_point start, Eigen::VectorXd& r, Eigen::VectorXd& scratch) {
    double replaced_at = residual;  // true residual when the recurrence last (re)started
    for (;;) {                      // one pass per (re)start of the recurrence from the true residual
      Pass pass;
      pass.started_at = report_.iterations;
      derived().run_pass(A, M, x, pass);
      if (!restart_from_true_residual(b, x, pass, scratch, r, replaced_at, start)) return;
    }
  }

  /// The end of a pass (BiCG, BiCGStab): the true residual, recomputed into `scratch`, decides.
  /// False: the solve is over (report final). True: the recurrence restarts from the true
  /// residual, now in `r` (report().restarts counts it; `replaced_at` is its value).
  bool restart_from_true_residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, const Pass& pass, Eigen::VectorXd& scratch,
                                  Eigen::VectorXd& r, double& replaced_at, Clock::time_point start) {
    const KrylovOptions& s = settings_;
    const double previous = replaced_at;
    report_.true_residual = true_residual(b, x, scratch);
    if (!std::isfinite(report_.true_residual))
      return finish(KrylovStatus::NonFinite, pass.stop ? pass.stop : "solution update", start), false;
    if (report_.true_residual <= s.tolerance) return finish(KrylovStatus::Converged, "", start), false;
    // A breakdown in the first step after a (re)start is final: restarting again would repeat it. Later ones
    // restart from the true residual with a fresh shadow vector (as Eigen's BiCGSTAB does for rho).
    if (pass.status == KrylovStatus::NonFinite || (pass.status == KrylovStatus::Breakdown && report_.iterations <= pass.started_at + 1))
      return finish(pass.status, pass.stop, start), false;
    if (report_.iterations >= s.max_iterations) return finish(KrylovStatus::IterationLimit, "", start), false;
    // The recurrence claimed convergence that the true residual does not confirm (residual gap):
    // restart from the true residual, unless the last pass did not even lower it.
    if (pass.status == KrylovStatus::NotComputed && report_.true_residual > (1.0 - s.stagnation_reduction) * previous)
      return finish(KrylovStatus::Stagnation, "", start), false;
    r = scratch;
    replaced_at = report_.true_residual;
    ++report_.restarts;
    return true;
  }

  /// Most iterations whose residual history is reserved before a solve (32 KiB).
  static constexpr int kHistoryReserveCap = 4096;

  KrylovOptions settings_;
  KrylovResult report_;
  const Operator* A_ = nullptr;
  const Preconditioner* M_ = nullptr;
  IdentityPreconditioner identity_;
  double b_norm_ = 0.0;
};

}  // namespace bemsurg
