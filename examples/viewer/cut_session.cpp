// examples/viewer/cut_session.cpp: the viewer's cut tool (see cut_session.hpp).
#include "cut_session.hpp"

#include <cstdio>

namespace bemsurg::viewer {

void CutSession::begin_drag(const Eigen::Vector3d& p, ModelWorker& worker, double gap_width) {
  worker_ = &worker;
  segments_.clear();
  dragging_ = false;
  const auto ph = worker.state();
  if (!ph || !ph->mesh) {
    ++refused_here_;
    reason_here_ = "no model loaded";
    return;
  }
  worker.prepare_cuts();  // the first step follows once the drag has moved (nothing to do when already ready)
  dragging_ = true;
  new_cut_ = true;
  gap_width_ = gap_width;
  last_point_ = p;
  step_length_ = 0.8 * ph->mean_edge;
  action_ = -1;
}

void CutSession::drag_to(const Eigen::Vector3d& p, ModelWorker& worker, double) {
  if (!dragging_) return;
  const Eigen::Vector3d d = p - last_point_;
  if (d.norm() < step_length_) return;
  segments_.emplace_back(last_point_, p);
  worker.request_cut_step(new_cut_, last_point_, d.normalized(), gap_width_);
  new_cut_ = false;
  last_point_ = p;
}

void CutSession::end_drag() {
  dragging_ = false;
  segments_.clear();
}

void CutSession::scripted_step(int action, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, ModelWorker& worker,
                               double gap_width) {
  worker_ = &worker;
  const bool new_cut = action != action_;
  action_ = action;
  worker.request_cut_step(new_cut, from, direction, gap_width);
  worker.wait_idle();
}

std::string CutSession::last_refusal() const {
  const std::string& r = counts().last_cut_refusal;
  return r.empty() ? reason_here_ : r;
}

std::string CutSession::status_line() const {
  const WorkerStatus st = counts();
  char buf[200];
  std::snprintf(
      buf, sizeof buf, "cut steps: %d accepted, %d refused; last step %.0f ms surface, %.0f ms first response, %.0f ms complete tables",
      accepted(), refused(), 1000.0 * st.last_cut_surface_seconds, 1000.0 * st.last_cut_first_seconds, 1000.0 * st.last_cut_update_seconds);
  std::string s = buf;
  if (st.cut_steps_waited > 0) s += "; " + std::to_string(st.cut_steps_waited) + " waited for the step before";
  if (!last_refusal().empty()) s += "\nlast refusal: " + last_refusal();
  return s;
}

std::string CutSession::summary() const {
  std::string s = "cuts: " + std::to_string(accepted()) + " steps accepted, " + std::to_string(refused()) + " refused";
  if (!last_refusal().empty()) s += " (last reason: " + last_refusal() + ")";
  return s;
}

}  // namespace bemsurg::viewer
