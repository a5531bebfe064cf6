// bemsurg/solvers/krylov_options.hpp: when the Krylov solvers (GMRES, BiCGStab, BiCG; Wang et
// al. 2007 §5.3) stop, and what they call a breakdown or stagnation. Shared by all three methods.
#pragma once

#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

/// When the Krylov solvers (GMRES, BiCGStab, BiCG; Wang et al. 2007 §5.3) stop, and what they call a breakdown or
/// stagnation. Shared by all three methods.
/// \ingroup solvers
struct KrylovOptions {
  /// Stop when the true relative residual ||b - A x|| / ||b|| is at most this.
  double tolerance = 1e-10;
  /// Stop (status iteration_limit) after this many iterations, i.e. products with A (BiCGStab
  /// counts one iteration per pair of products, as Eigen and the paper's Table 1 do).
  int max_iterations = 1000;
  /// GMRES only: restart length m of GMRES(m); 0 = no restart (full GMRES, the paper's choice).
  /// The basis then holds min(max_iterations, n) + 1 vectors.
  int restart = 0;
  /// A scalar the recurrence divides by counts as vanished ("breakdown") when it is below this
  /// times the product of the norms of the vectors it is made of (a cosine below 1e-13).
  double breakdown_tolerance = 1e-13;
  /// Stagnation: a GMRES(m) cycle, or a stretch between two residual replacements in BiCG and
  /// BiCGStab, that lowers the true residual by less than this fraction of itself.
  double stagnation_reduction = 1e-3;

  /// Throws SolverError naming the first field that makes no sense.
  void validate() const {
    if (!(std::isfinite(tolerance) && tolerance > 0.0))
      throw SolverError("Krylov settings: tolerance must be a positive finite number, got " + number_text(tolerance));
    if (max_iterations < 1) throw SolverError("Krylov settings: max_iterations must be at least 1, got " + std::to_string(max_iterations));
    if (restart < 0) throw SolverError("Krylov settings: restart must be 0 (no restart) or positive, got " + std::to_string(restart));
    if (!(std::isfinite(breakdown_tolerance) && breakdown_tolerance >= 0.0 && breakdown_tolerance < 1.0))
      throw SolverError("Krylov settings: breakdown_tolerance must lie in [0, 1), got " + number_text(breakdown_tolerance));
    if (!(std::isfinite(stagnation_reduction) && stagnation_reduction >= 0.0 && stagnation_reduction < 1.0))
      throw SolverError("Krylov settings: stagnation_reduction must lie in [0, 1), got " + number_text(stagnation_reduction));
  }
};

/// Deprecated name (before 0.2), kept one minor version: use KrylovOptions.

using KrylovSettings [[deprecated("renamed to KrylovOptions in bemsurg 0.2")]] = KrylovOptions;

}  // namespace bemsurg
