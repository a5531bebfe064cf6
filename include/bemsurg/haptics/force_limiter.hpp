// bemsurg/haptics/force_limiter.hpp: the last stage before a force reaches a haptic device.
// Whatever the simulation computed, the device receives a finite force no larger than the
// device's limit, and its rate of change is bounded so a contact switch cannot kick the hand.
// The rate limit is per second (N/s), so the same settings mean the same feel at 1 kHz and 10 kHz.
#pragma once

#include <Eigen/Core>

namespace bemsurg::haptics {

/// The last stage before a force reaches a haptic device: the device receives a finite force no larger than max_force, whose
/// change is bounded by max_rate newtons per second so a contact switch cannot kick the hand.
/// \ingroup haptics
class ForceLimiter {
 public:
  /// max_force in newtons (3.3 N suits a Touch-class desktop device); max_rate in newtons per
  /// second: the largest change of the sent force per second of loop time. Throws
  /// InvalidArgumentError unless both are finite and positive.
  ForceLimiter(double max_force, double max_rate);

  /// Returns the force to send `dt` seconds after the last one: non-finite input (or a
  /// non-finite or negative dt) gives the last sent force (held, never NaN); the change from the
  /// last sent force is clipped to max_rate * dt and the magnitude to max_force. Allocation-free.
  Eigen::Vector3d operator()(const Eigen::Vector3d& requested, double dt) noexcept;

  /// Forgets the last force (the next call ramps from zero).
  void reset() noexcept { last_.setZero(); }
  /// Sets the last sent force (e.g. zero after the device was told zero by someone else).
  void set_last(const Eigen::Vector3d& f) noexcept { last_ = f; }
  double max_force() const { return max_force_; }
  double max_rate() const { return max_rate_; }
  const Eigen::Vector3d& last() const { return last_; }

 private:
  double max_force_;
  double max_rate_;
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
};

}  // namespace bemsurg::haptics
