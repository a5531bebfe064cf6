// examples/viewer/cut_session.hpp: the viewer's cut tool (Wang et al. 2007 §5.3, docs/design.md §7).
// A left-drag with the cut tool opens a cut at the surface vertex nearest the press and extends it
// by one edge each time the mouse has travelled about one edge length along the surface; a script's
// "cut" action does the same with its steps. Each step goes to the ModelWorker, which takes it
// through the library's one cut entry point (bemsurg::CutSystemUpdate: the same rules as `bemsurg
// cut` and sessions), shows the new surface at once and brings the tables up to date behind it. A
// refused step shows its reason in the window (and on stderr in headless mode) and changes nothing.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "model_worker.hpp"

namespace bemsurg::viewer {

class CutSession {
 public:
  /// Interactive: press at p (a surface point), drag along the surface, release.
  void begin_drag(const Eigen::Vector3d& p, ModelWorker& worker, double gap_width);
  void drag_to(const Eigen::Vector3d& p, ModelWorker& worker, double gap_width);
  void end_drag();

  /// Scripted: one increment of the cut started by script action `action` (a new action opens a
  /// new cut). Waits for the tables (headless playback is deterministic).
  void scripted_step(int action, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, ModelWorker& worker, double gap_width);

  /// Segments of the current drag (drawn as a line while cutting).
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& path_segments() const { return segments_; }
  /// One line for the window: last step, accepted/refused counts, the last refusal's reason.
  std::string status_line() const;
  /// For headless output: "cuts: A steps accepted, R refused (last reason: ...)".
  std::string summary() const;
  int accepted() const { return counts().cut_steps_accepted; }
  int refused() const { return counts().cut_steps_refused + refused_here_; }
  std::string last_refusal() const;

 private:
  WorkerStatus counts() const { return worker_ ? worker_->status() : WorkerStatus(); }

  const ModelWorker* worker_ = nullptr;  // the worker the steps went to (it counts them)
  int refused_here_ = 0;                 // refused before reaching the worker (no model yet)
  std::string reason_here_;
  bool dragging_ = false;
  bool new_cut_ = false;
  int action_ = -1;
  double gap_width_ = 0.0;
  Eigen::Vector3d last_point_ = Eigen::Vector3d::Zero();
  double step_length_ = 0.0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments_;
};

}  // namespace bemsurg::viewer
