// Implementation of bemsurg/haptics/force_limiter.hpp (allocation-free; called at haptic rate).
#include "bemsurg/haptics/force_limiter.hpp"

#include <cmath>

#include "bemsurg/error.hpp"

namespace bemsurg::haptics {

ForceLimiter::ForceLimiter(double max_force, double max_rate) : max_force_(max_force), max_rate_(max_rate) {
  if (!(max_force > 0.0) || !std::isfinite(max_force) || !(max_rate > 0.0) || !std::isfinite(max_rate))
    throw InvalidArgumentError("ForceLimiter: max_force (N) and max_rate (N/s) must be finite and positive");
}

namespace {
/// Scales v down to length `limit` when it is longer. v is divided by its largest component
/// first, so the length is computed from components in [-1, 1] and cannot overflow to inf (a
/// request of 1e200 or DBL_MAX would otherwise clip to zero and freeze) or underflow to zero.
void clip_length(Eigen::Vector3d& v, double limit) noexcept {
  const double largest = v.cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) return;
  const Eigen::Vector3d scaled = v / largest;
  const double n = scaled.stableNorm();  // in [1, sqrt 3]
  if (largest > limit / n) v = scaled * (limit / n);
}
}  // namespace

Eigen::Vector3d ForceLimiter::operator()(const Eigen::Vector3d& requested, double dt) noexcept {
  if (!requested.allFinite() || !(dt >= 0.0) || !std::isfinite(dt)) return last_;
  Eigen::Vector3d step = requested - last_;  // finite: |last_| <= max_force
  const double max_step = max_rate_ * dt;
  if (!(max_step > 0.0)) return last_;
  clip_length(step, max_step);
  Eigen::Vector3d out = last_ + step;
  clip_length(out, max_force_);
  last_ = out;
  return out;
}

}  // namespace bemsurg::haptics
