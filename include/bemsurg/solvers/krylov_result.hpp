// bemsurg/solvers/krylov_result.hpp: what a Krylov solve says about itself (the paper's
// Table 1 reports iterations and CPU time of GMRES, BiCGStab and BiCG after a cut). A solver never
// calls a wrong answer converged: "converged" means the residual b - A x, recomputed from x at the
// end (not the recurrence's running estimate), met the tolerance.
#pragma once

#include <Eigen/Core>
#include <charconv>
#include <string>

#include <vector>
#include "bemsurg/number_text.hpp"

namespace bemsurg {

/// How a Krylov solve ended (KrylovResult::status; to_string gives the names reports use).
/// \ingroup solvers
enum class KrylovStatus {
  Converged,       // true relative residual <= tolerance
  IterationLimit,  // max_iterations reached first
  Breakdown,       // a scalar the recurrence divides by vanished; `breakdown` names it
  Stagnation,      // restarts / residual replacements stopped lowering the true residual
  NonFinite,       // NaN or infinity in the data or in the iteration
  NotComputed      // no solve yet
};

/// "converged", "iteration_limit", "breakdown", "stagnation", "non_finite", "not_computed":
/// the strings report.json and LinearSolveResult::status use.
inline const char* to_string(KrylovStatus status) {
  switch (status) {
    case KrylovStatus::Converged: return "converged";
    case KrylovStatus::IterationLimit: return "iteration_limit";
    case KrylovStatus::Breakdown: return "breakdown";
    case KrylovStatus::Stagnation: return "stagnation";
    case KrylovStatus::NonFinite: return "non_finite";
    case KrylovStatus::NotComputed: return "not_computed";
  }
  return "unknown";
}

/// What a Krylov solve says about itself: status, iterations, restarts, residuals and wall time. Converged means the true
/// residual b - A x, recomputed from the returned x, met the tolerance.
/// \ingroup solvers
struct KrylovResult {
  KrylovStatus status = KrylovStatus::NotComputed;
  /// For Breakdown: which quantity vanished, e.g. "rho = (r0~, r)"; for NonFinite: where the
  /// first NaN/infinity appeared; empty otherwise.
  std::string breakdown;
  int iterations = 0;               // products with A inside the iteration (BiCGStab: steps)
  int restarts = 0;                 // GMRES(m) cycles after the first; residual replacements in BiCG(Stab)
  double initial_residual = 0.0;    // ||b - A x0|| / ||b||
  double true_residual = 0.0;       // ||b - A x|| / ||b||, recomputed from the returned x
  double estimated_residual = 0.0;  // the recurrence's last estimate (for comparison only)
  /// Relative residual estimate after each iteration, starting with the initial residual; the
  /// capacity is reused between solves, so a warm solver allocates nothing here (up to 4096
  /// iterations are reserved before a solve; a longer run grows it, and keeps the capacity).
  std::vector<double> residual_history;
  double seconds = 0.0;  // wall time of the solve (not of compute())

  bool converged() const { return status == KrylovStatus::Converged; }
  Eigen::ComputationInfo info() const {
    switch (status) {
      case KrylovStatus::Converged: return Eigen::Success;
      case KrylovStatus::IterationLimit:
      case KrylovStatus::Stagnation: return Eigen::NoConvergence;
      default: return Eigen::NumericalIssue;
    }
  }
  /// One line for logs and exceptions: status, quantity, iterations, residual.
  std::string summary() const {
    std::string s = to_string(status);
    if (!breakdown.empty()) s += " (" + breakdown + ")";
    s += " after " + std::to_string(iterations) + " iterations, true relative residual " + scientific_text(true_residual, 3);
    return s;
  }
};

/// Deprecated name (before 0.2), kept one minor version: use KrylovResult.

using KrylovReport [[deprecated("renamed to KrylovResult in bemsurg 0.2")]] = KrylovResult;

}  // namespace bemsurg
