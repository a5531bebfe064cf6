// examples/viewer/cut_session.cpp: the viewer's cut tool (see cut_session.hpp).
#include "cut_session.hpp"

#include <chrono>
#include <cstdio>

namespace bemsurg::viewer {

namespace {
const char* kNoCutter =
    "cutting is not in this build: it needs the cutting module (bemsurg::SurfaceCutter, "
    "include/bemsurg/cutting/surface_cutter.hpp)";
}

bool CutSession::start_cut(ModelWorker& worker, double gap_width, std::string& why) {
#if BEMSURG_VIEWER_HAS_CUTTER
  const auto ph = worker.state();
  if (!ph || !ph->mesh) {
    why = "no model loaded";
    return false;
  }
  if (sent_mesh_ && ph->mesh != sent_mesh_) {
    // Either the worker has not yet taken the last cut, or a different model was loaded since.
    if (ph->mesh->num_elements() < sent_mesh_->num_elements() && ph->cuts > 0) {
      why = "the previous cut is still being taken in: try again in a moment";
      return false;
    }
    sent_mesh_.reset();
  }
  CutOptions options;
  options.gap_width = gap_width;  // 0: the cutter's default fraction of the local edge length
  std::vector<char> locks = ph->supported;
  locks.resize(static_cast<std::size_t>(ph->mesh->num_elements()), 0);
  cutter_ = std::make_unique<SurfaceCutter>(ph->mesh, std::move(locks), options);
  step_length_ = 0.8 * ph->mean_edge;
  return true;
#else
  (void)worker;
  (void)gap_width;
  why = kNoCutter;
  return false;
#endif
}

bool CutSession::step(const Eigen::Vector3d& from, const Eigen::Vector3d& direction, ModelWorker& worker) {
#if BEMSURG_VIEWER_HAS_CUTTER
  if (!cutter_) return false;
  const auto t0 = std::chrono::steady_clock::now();
  CutStep s;
  try {
    s = cutter_->step(from, direction);
  } catch (const std::exception& e) {
    s.accepted = false;
    s.reason = e.what();
  }
  last_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!s.accepted) {
    ++refused_;
    last_reason_ = s.reason.empty() ? "refused (no reason given)" : s.reason;
    return false;
  }
  ++accepted_;
  sent_mesh_ = cutter_->mesh();
  worker.apply_cut(sent_mesh_, s.delta);
  return true;
#else
  (void)from;
  (void)direction;
  (void)worker;
  ++refused_;
  last_reason_ = kNoCutter;
  return false;
#endif
}

void CutSession::begin_drag(const Eigen::Vector3d& p, ModelWorker& worker, double gap_width) {
  segments_.clear();
  dragging_ = false;
  std::string why;
  if (!start_cut(worker, gap_width, why)) {
    ++refused_;
    last_reason_ = why;
    return;
  }
  dragging_ = true;
  last_point_ = p;
  action_ = -1;
}

void CutSession::drag_to(const Eigen::Vector3d& p, ModelWorker& worker, double) {
  if (!dragging_) return;
  const Eigen::Vector3d d = p - last_point_;
  if (d.norm() < step_length_) return;
  segments_.emplace_back(last_point_, p);
  step(last_point_, d.normalized(), worker);
  last_point_ = p;
}

void CutSession::end_drag() {
  dragging_ = false;
  segments_.clear();
}

void CutSession::scripted_step(int action, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, ModelWorker& worker,
                               double gap_width) {
  if (action != action_) {
    action_ = action;
    std::string why;
    if (!start_cut(worker, gap_width, why)) {
      ++refused_;
      last_reason_ = why;
      return;
    }
  }
  if (step(from, direction, worker)) worker.wait_idle();
}

std::string CutSession::status_line() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "cut steps: %d accepted, %d refused; last step %.0f ms", accepted_, refused_, 1000.0 * last_seconds_);
  std::string s = buf;
  if (!available())
    s += "\n" + std::string(kNoCutter);
  else if (!last_reason_.empty())
    s += "\nlast refusal: " + last_reason_;
  return s;
}

std::string CutSession::summary() const {
  std::string s = "cuts: " + std::to_string(accepted_) + " steps accepted, " + std::to_string(refused_) + " refused";
  if (!last_reason_.empty()) s += " (last reason: " + last_reason_ + ")";
  return s;
}

}  // namespace bemsurg::viewer
