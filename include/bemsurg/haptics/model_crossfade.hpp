// bemsurg/haptics/model_crossfade.hpp: how the delivered force passes from an old contact model to
// a new one (a cut step, a change of E or nu, a recomputed table, a re-placed or engaged tool):
// both are evaluated at the device's pose and the force is blended linearly from the old model's
// to the new one's over `duration` seconds instead of switching (docs/haptics.md, "Model swaps").
// The old model stays a valid linear model of the tissue it was built for (Wang et al. 2007 §5.3
// render the uncut model until the updated one is ready), so the blend only spreads the
// difference between two valid forces over time: at 1 kHz and 30 ms, each tick moves 1/30 of it.
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace bemsurg::haptics {

/// Default blend time: long enough that a swap changes the force by at most ~3 % of the models'
/// difference per 1 kHz tick, short enough (below the ~50 ms a hand resolves as a separate event)
/// that a new contact or a released tool is felt at once (docs/haptics.md, "Model swaps").
constexpr double kDefaultModelBlendSeconds = 0.03;

/// The weight of the new model in a blend that started at `start` (session seconds) and lasts
/// `duration`: 0 at the start, 1 from start + duration on, linear between. Allocation-free and
/// noexcept: the haptic thread and the viewer's tick call it.
/// \ingroup haptics
class ModelCrossfade {
 public:
  explicit ModelCrossfade(double duration = kDefaultModelBlendSeconds) noexcept : duration_(duration) {}
  /// A new model was taken at session time `now`: the blend starts (a duration <= 0 switches at once).
  void start(double now) noexcept {
    start_ = now;
    active_ = duration_ > 0.0;
  }
  /// The new model's weight at `now`; ends the blend (active() false) once it reaches 1.
  double weight(double now) noexcept {
    if (!active_) return 1.0;
    const double w = std::clamp((now - start_) / duration_, 0.0, 1.0);
    if (w >= 1.0) active_ = false;
    return w;
  }
  /// (1 - w) old + w new.
  static Eigen::Vector3d mix(const Eigen::Vector3d& old_force, const Eigen::Vector3d& new_force, double w) noexcept {
    return old_force + w * (new_force - old_force);
  }
  bool active() const noexcept { return active_; }
  double duration() const noexcept { return duration_; }
  void set_duration(double seconds) noexcept { duration_ = seconds; }

 private:
  double duration_;
  double start_ = 0.0;
  bool active_ = false;
};

}  // namespace bemsurg::haptics
