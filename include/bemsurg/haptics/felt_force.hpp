// bemsurg/haptics/felt_force.hpp: what a hand on the device feels, as two numbers per run
// (docs/haptics.md, "Force continuity"): over the ticks where a tool's contact-model force is at
// least 10 % of its peak, the smallest ratio of the force delivered to the model's (a fade shows
// as a ratio near 0) and the largest tick-to-tick change of the delivered force relative to the
// model force (a drop to zero counts as 1). The older max_force_jump_fraction looks at the model
// force alone and skips ticks below 10 % of the peak on either side, so it cannot see a fade.
// Both are changes per loop period: a change across a late tick (a stalled scheduler on a shared
// machine, the gap g since the tool's previous tick longer than the period T) counts as the
// change times T / g, since the script moved on in real time while the model did not step.
// Sessions (`bemsurg session`'s report.json) and the viewer's headless mode both report these.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace bemsurg::haptics {

/// The two figures and where they occurred (tool index, session seconds).
/// \ingroup haptics
struct FeltForce {
  double min_delivered_ratio = 1.0;  // 1 when no tick qualifies
  double min_delivered_ratio_time = 0.0;
  int min_delivered_ratio_tool = -1;
  double max_tick_change_fraction = 0.0;
  double max_tick_change_time = 0.0;
  int max_tick_change_tool = -1;
};

/// Collects ticks (off the haptic thread) and computes FeltForce once the peaks are known.
/// \ingroup haptics
class FeltForceRecorder {
 public:
  /// `max_force`: the device's magnitude limit (N). The model force counts up to it: clamping is
  /// a safety stage, not a fade. `period`: the loop's nominal period (s); 0 takes every change as
  /// it is, whatever the gap between ticks.
  explicit FeltForceRecorder(int tools, double max_force, double period = 0.0)
      : max_force_(max_force), period_(period), peak_(static_cast<std::size_t>(tools), 0.0), last_(static_cast<std::size_t>(tools)) {}

  /// How many nominal periods a tick's gap `gap` spans, at least 1 (the divisor of a late tick's
  /// change). Shared with the session's model-force metric.
  static double periods_spanned(double gap, double period) { return period > 0.0 && gap > period ? gap / period : 1.0; }

  /// One tick of tool `tool`: the contact model's force and the force delivered to the device.
  void add(int tool, double time, const Eigen::Vector3d& model, const Eigen::Vector3d& delivered) {
    const auto t = static_cast<std::size_t>(tool);
    const double m = model.norm();
    peak_[t] = std::max(peak_[t], m);
    Last& l = last_[t];
    const double spans = l.seen ? periods_spanned(time - l.time, period_) : 1.0;
    ticks_.push_back({time, tool, m, delivered.norm(), (delivered - l.delivered).norm() / spans, l.seen ? l.model : -1.0});
    l = {true, time, m, delivered};
  }

  FeltForce result() const {
    FeltForce r;
    for (const Tick& k : ticks_) {
      const double threshold = 0.1 * peak_[static_cast<std::size_t>(k.tool)];
      if (!(threshold > 0.0) || k.model < threshold) continue;
      const double ratio = k.delivered / std::min(k.model, max_force_);
      if (ratio < r.min_delivered_ratio) r = with_ratio(r, ratio, k);
      if (k.model_before < threshold) continue;
      const double change = k.change / std::min(std::max(k.model, k.model_before), max_force_);
      if (change > r.max_tick_change_fraction) {
        r.max_tick_change_fraction = change;
        r.max_tick_change_time = k.time;
        r.max_tick_change_tool = k.tool;
      }
    }
    return r;
  }

 private:
  struct Tick {
    double time;
    int tool;
    double model, delivered;
    double change;        // per nominal period (periods_spanned)
    double model_before;  // -1 on a tool's first tick
  };
  struct Last {
    bool seen = false;
    double time = 0.0;
    double model = 0.0;
    Eigen::Vector3d delivered = Eigen::Vector3d::Zero();
  };
  static FeltForce with_ratio(FeltForce r, double ratio, const Tick& k) {
    r.min_delivered_ratio = ratio;
    r.min_delivered_ratio_time = k.time;
    r.min_delivered_ratio_tool = k.tool;
    return r;
  }
  double max_force_;
  double period_;
  std::vector<double> peak_;
  std::vector<Last> last_;
  std::vector<Tick> ticks_;
};

}  // namespace bemsurg::haptics
