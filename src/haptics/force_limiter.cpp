// Implementation of bemsurg/haptics/force_limiter.hpp (allocation-free; called at haptic rate).
#include "bemsurg/haptics/force_limiter.hpp"

#include <cmath>
#include <stdexcept>

namespace bemsurg::haptics {

ForceLimiter::ForceLimiter(double max_force, double max_step) : max_force_(max_force), max_step_(max_step) {
  if (!(max_force > 0.0) || !std::isfinite(max_force) || !(max_step > 0.0) || !std::isfinite(max_step))
    throw std::invalid_argument("ForceLimiter: max_force and max_step must be finite and positive");
}

Eigen::Vector3d ForceLimiter::operator()(const Eigen::Vector3d& requested) {
  if (!requested.allFinite()) return last_;
  Eigen::Vector3d step = requested - last_;
  const double step_norm = step.norm();
  if (step_norm > max_step_) step *= max_step_ / step_norm;
  Eigen::Vector3d out = last_ + step;
  const double norm = out.norm();
  if (norm > max_force_) out *= max_force_ / norm;
  last_ = out;
  return out;
}

}  // namespace bemsurg::haptics
