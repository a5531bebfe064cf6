// examples/viewer/cut_session.hpp: the viewer's cut tool (Wang et al. 2007 §5.3, docs/design.md §7).
// A left-drag with the cut tool opens a cut at the surface vertex nearest the press and extends it
// by one edge each time the mouse has travelled about one edge length along the surface; a script's
// "cut" action does the same with its steps. The topology is bemsurg::SurfaceCutter (the cutting
// module); the new surface is handed to the ModelWorker, which shows it at once and brings the
// tables up to date in the background. A refused step shows its reason in the window (and on
// stderr in headless mode) and changes nothing.
//
// The cutting module is optional at compile time: without include/bemsurg/cutting/surface_cutter.hpp
// the tool says so instead of cutting.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "model_worker.hpp"

#if __has_include("bemsurg/cutting/surface_cutter.hpp")
#define BEMSURG_VIEWER_HAS_CUTTER 1
#include "bemsurg/cutting/surface_cutter.hpp"
#else
#define BEMSURG_VIEWER_HAS_CUTTER 0
#endif

namespace bemsurg::viewer {

class CutSession {
 public:
  static bool available() { return BEMSURG_VIEWER_HAS_CUTTER != 0; }

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
  int accepted() const { return accepted_; }
  int refused() const { return refused_; }
  const std::string& last_refusal() const { return last_reason_; }

 private:
  bool start_cut(ModelWorker& worker, double gap_width, std::string& why);
  bool step(const Eigen::Vector3d& from, const Eigen::Vector3d& direction, ModelWorker& worker);

  int accepted_ = 0, refused_ = 0;
  std::string last_reason_;
  double last_seconds_ = 0.0;
  bool dragging_ = false;
  int action_ = -1;
  Eigen::Vector3d last_point_ = Eigen::Vector3d::Zero();
  double step_length_ = 0.0;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments_;
#if BEMSURG_VIEWER_HAS_CUTTER
  std::unique_ptr<SurfaceCutter> cutter_;
#endif
  std::shared_ptr<const TriangleMesh> sent_mesh_;  // the last surface handed to the worker
};

}  // namespace bemsurg::viewer
