// bemsurg/haptics/force_limiter.hpp: the last stage before a force reaches a haptic device.
// Whatever the simulation computed, the device receives a finite force no larger than the
// device's limit, and its rate of change is bounded so a contact switch cannot kick the hand.
#pragma once

#include <Eigen/Core>

namespace bemsurg::haptics {

class ForceLimiter {
 public:
  /// max_force in newtons; max_step is the largest change allowed between two consecutive calls.
  ForceLimiter(double max_force, double max_step);

  /// Returns the force to send: non-finite input becomes the last sent force (held, never NaN),
  /// the change from the last sent force is clipped to max_step and the magnitude to max_force.
  Eigen::Vector3d operator()(const Eigen::Vector3d& requested);

  void reset() { last_.setZero(); }
  double max_force() const { return max_force_; }

 private:
  double max_force_;
  double max_step_;
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
};

}  // namespace bemsurg::haptics
