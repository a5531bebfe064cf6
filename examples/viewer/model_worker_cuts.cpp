// examples/viewer/model_worker_cuts.cpp: the worker's cut steps (see model_worker.hpp): requests from
// the window's thread, the steps themselves on the worker's thread through the one cut entry point
// (CutSystemUpdate), in two phases when the tools' places are known, and the storage made ready
// before the first step (prepare_cuts).
#include <cmath>
#include <new>

#include "bemsurg/timing.hpp"
#include "model_worker.hpp"

namespace bemsurg::viewer {

void ModelWorker::request_cut_step(bool new_cut, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, double gap_width) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    cuts_pending_.push_back({new_cut, from, direction, gap_width});
    if (cutting_) ++status_.cut_steps_waited;
    busy_ = true;
  }
  wake_.notify_all();
}

void ModelWorker::prepare_cuts() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_.prepare_cuts = true;
    busy_ = true;
  }
  wake_.notify_all();
}

void ModelWorker::use_cut_system_of_reference() {
  if (cut_system_ && cut_system_->table() == reference_) return;
  cut_system_ = std::make_unique<CutSystemUpdate>(reference_);
  cuts_prepared_ = false;
}

void ModelWorker::do_prepare_cuts() {
  if (!loaded_ || !reference_ || !reference_->has_factorization()) return;  // a cut would be refused anyway
  use_cut_system_of_reference();
  if (cuts_prepared_) return;
  try {
    cut_system_->reserve_snapshot_buffers();
  } catch (const std::bad_alloc&) {
    return;  // only saves time: the steps allocate their tables as they go
  }
  cuts_prepared_ = true;
  count_cut_buffers();
}

void ModelWorker::count_cut_buffers() {
  if (!cut_system_) return;
  const SnapshotBufferPool::Counts c = cut_system_->snapshot_buffer_counts();
  std::lock_guard<std::mutex> lock(mutex_);
  status_.cut_buffers_allocated = c.allocated;
  status_.cut_buffers_reused = c.reused;
  status_.cut_buffers_held = c.held;
}

void ModelWorker::refuse_cut(const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++status_.cut_steps_refused;
  status_.last_cut_refusal = reason.empty() ? "refused (no reason given)" : reason;
}

void ModelWorker::do_cut(const CutRequest& cut) {
  if (!loaded_ || !reference_ || !reference_->has_factorization()) {
    refuse_cut(loaded_ ? "the tables are not ready yet: try again in a moment" : "no model loaded");
    return;
  }
  // The one cut entry point (docs/design.md §7): its rules lock held and loaded elements, carry the
  // conditions over and grow the table's region; the viewer only shows what it returns.
  use_cut_system_of_reference();
  if (cut.new_cut) {
    CutOptions options;
    options.gap_width = cut.gap_width;  // 0: the cutter's default fraction of the local edge length
    cut_system_->begin_cut(options);
  }
  auto t0 = SteadyClock::now();
  const CutSurfaceStep surface = cut_system_->cut_surface(cut.from, cut.direction);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.last_cut_surface_seconds = seconds_since(t0);
  }
  if (!surface.accepted) {
    refuse_cut(surface.reason);
    return;
  }
  const std::shared_ptr<const TriangleMesh>& mesh = surface.mesh;
  const auto previous = state();
  const std::shared_ptr<PhysicsState> s = provisional_state(mesh, previous);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.tables_exact = false;
  }
  publish(s);
  // The exact tables for the cut surface: the delta update of the kept factorisation (rows and
  // columns of the changed elements only), in two phases when the tools' places are known.
  set_status(WorkerPhase::Precomputing, "updating the tables for the cut (" + std::to_string(surface.delta.added.size()) + " new, " +
                                            std::to_string(surface.delta.modified.size()) + " modified elements)");
  std::vector<Eigen::Vector3d> points;
  double reach = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    points = reach_points_;
    reach = reach_;
  }
  t0 = SteadyClock::now();
  std::shared_ptr<const GreensTable> first;
  const CutStepResult r = reach > 0.0 ? cut_system_->apply_first(surface, points, reach, first) : cut_system_->apply(surface);
  if (!r.accepted) {  // undone: the model before the step comes back
    if (previous) publish(std::make_shared<PhysicsState>(*previous));
    refuse_cut(r.reason);
    std::lock_guard<std::mutex> lock(mutex_);
    status_.tables_exact = true;
    status_.phase = WorkerPhase::Ready;
    status_.message = "ready";
    return;
  }
  if (first) {
    // The first response: exact for the region elements within the tools' reach, published at once
    // (the tools blend into it); the complete table follows on this thread, and a step asked for
    // meanwhile waits in cuts_pending_.
    follow_cut(mesh, *s, *first, false);
    publish(state_for(first));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++status_.cut_first_responses;
      status_.last_cut_first_seconds = seconds_since(t0);
      status_.first_response = true;
      status_.tables_exact = true;
    }
    cut_system_->complete_step();
  } else {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.last_cut_first_seconds = 0.0;
  }
  cut_system_->wait_for_refactor();  // headless playback stays deterministic
  reference_ = cut_system_->table();
  count_cut_buffers();
  follow_cut(mesh, *s, *reference_, true);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++status_.cut_steps_accepted;
    status_.last_cut_update_seconds = seconds_since(t0);
    status_.first_response = false;
  }
  do_rescale();
}

void ModelWorker::set_cutting(bool on) {
  std::lock_guard<std::mutex> lock(mutex_);
  cutting_ = on;
}

void ModelWorker::set_cut_reach(std::vector<Eigen::Vector3d> points, double reach) {
  std::lock_guard<std::mutex> lock(mutex_);
  reach_points_ = std::move(points);
  reach_ = std::isfinite(reach) && reach > 0.0 ? reach : 0.0;
}

}  // namespace bemsurg::viewer
