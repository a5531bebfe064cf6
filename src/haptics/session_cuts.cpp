// Implementation of bemsurg/haptics/session.hpp, its cut steps: one at a time in time order, each in
// two phases in real-time sessions (a first response within the tools' reach, then the complete
// table), handed to the loop as new models (docs/haptics.md, "Feeling through a cut").
#include <algorithm>
#include <chrono>
#include <cmath>

#include "bemsurg/error.hpp"
#include "bemsurg/haptics/session.hpp"
#include "session_text.hpp"

namespace bemsurg::haptics {

using detail::centroid;
using detail::describe;

void Session::apply_cut(const CutResult& r, const ScheduledCut& c, SessionObserver* observer, SessionResult& result) {
  const Action& a = script_.actions[static_cast<std::size_t>(c.action)];
  if (!r.mesh || !r.table) throw ContactError(describe(script_, a) + ": the cut hook returned no mesh or table");
  mesh_ = r.mesh;
  table_ = r.table;
  ++result.cuts;
  if (observer) observer->on_cut(result.cuts, *mesh_);
  dirty_ = true;
}

void Session::complete_cut(const CutResult& r, ScheduledCut& c, SessionResult& result) {
  // The second phase of a step: the complete table of the same mesh, handed to the loop (blended in).
  if (!r.table)
    throw ContactError(describe(script_, script_.actions[static_cast<std::size_t>(c.action)]) + ": the cut's completion returned no table");
  if (r.table != table_) {  // a first response that covered the whole region is the complete table already
    table_ = r.table;
    dirty_ = true;
  }
  c.done = true;
  completing_ = false;
  result.cut_complete_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - cut_requested_).count());
}

std::vector<Eigen::Vector3d> Session::reach_points(double& reach) const {
  // Every tool's tip, where it holds or slides from, a plate's polygon (where its elements are
  // collected, sampled finer than the margin) and the centroid of every element in contact now (a
  // deep press holds elements along its path), and the largest of their reaches: radius x (1 +
  // slide margin) + the margin a tool may move while the step completes.
  std::vector<Eigen::Vector3d> points;
  for (Index e : in_contact_)
    if (e >= 0 && e < mesh_->num_elements()) points.push_back(mesh_->centroid(e));
  reach = options_.reach_margin;
  for (std::size_t t = 0; t < script_.tools.size(); ++t) {
    const ScriptTool& tool = script_.tools[t];
    points.push_back(position_[t]);
    const Engagement& e = engagement_[t];
    if (e.active || e.placed) points.push_back(e.at);  // what it holds or slides from (a pinch may have pulled away from it)
    const bool plate = tool.polygon.size() >= 3;
    reach = std::max(reach, options_.tool_reach(tool.radius, plate ? tool.plate_tolerance : 0.0));
    if (!plate) continue;
    const Eigen::Vector3d c = centroid(tool.polygon);
    for (std::size_t i = 0; i < tool.polygon.size(); ++i) {  // fan triangles (c, a, b), a barycentric grid on each
      const Eigen::Vector3d a = tool.polygon[i], b = tool.polygon[(i + 1) % tool.polygon.size()];
      const double size = std::max({(a - c).norm(), (b - c).norm(), (b - a).norm()});
      const int k = std::max(1, static_cast<int>(std::ceil(size / std::max(1e-9, options_.reach_margin))));
      for (int u = 0; u <= k; ++u)
        for (int v = 0; u + v <= k; ++v) points.push_back(c + (double(u) / k) * (a - c) + (double(v) / k) * (b - c));
    }
  }
  return points;
}

void Session::run_cuts(double now, SessionObserver* observer, SessionResult& result) {
  // Cuts, off the haptic thread, one step at a time in time order; the loop renders the old model
  // until the new one is offered and blended in. In a real-time session a step runs on a
  // background thread and this side stays alive (heartbeat, events, models on the old snapshots).
  // A step answers in two phases when the hook gives a completion (options_.first_response): the
  // first response (the columns within the tools' reach) is handed to the loop at once, the complete
  // table follows before the next step starts; a step due meanwhile waits, and is counted.
  if (cut_task_.busy()) {
    ScheduledCut& c = cuts_[cut_in_flight_];
    if (cut_task_.ready()) {
      CutResult r = cut_task_.take();  // the hook's error is rethrown here
      if (completing_) {
        complete_cut(r, c, result);
      } else {
        result.cut_step_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - cut_requested_).count());
        apply_cut(r, c, observer, result);
        if (r.complete) {
          completing_ = true;
          cut_task_.start([complete = r.complete, mesh = r.mesh] { return CutResult{mesh, complete(), {}}; }, thread_budget_);
        } else {
          c.done = true;
          result.cut_complete_seconds.push_back(result.cut_step_seconds.back());
        }
      }
    } else if (cut_task_.seconds() > options_.max_step_s && !hung_) {
      hung_ = true;  // stop beating: the watchdog fades the force; run() ends the session
      hung_since_ = now;
    }
    if (cut_task_.busy()) {
      for (std::size_t i = cut_in_flight_ + 1; i < cuts_.size() && cuts_[i].time <= now; ++i)
        if (!cuts_[i].waited) {
          cuts_[i].waited = true;
          ++result.cut_steps_waited;
        }
    }
    return;
  }
  for (std::size_t i = 0; i < cuts_.size(); ++i) {
    ScheduledCut& c = cuts_[i];
    if (c.done) continue;
    if (c.time > now) return;
    const Action& a = script_.actions[static_cast<std::size_t>(c.action)];
    CutRequest req{mesh_, table_, a.from, a.direction, c.step, c.action, {}, 0.0};
    const bool background = in_realtime_ && options_.background_steps;
    if (options_.first_response && background) req.tools = reach_points(req.reach);
    cut_requested_ = std::chrono::steady_clock::now();
    if (background) {
      cut_in_flight_ = i;
      completing_ = false;
      cut_task_.start([hook = options_.cut_hook, req] { return hook(req); }, thread_budget_);
      return;
    }
    // In line (virtual clock, or background steps off): one phase, since nothing could be rendered
    // between two (a hook that still gives a completion has it run at once).
    const CutResult r = options_.cut_hook(req);
    result.cut_step_seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - cut_requested_).count());
    apply_cut(r, c, observer, result);
    if (r.complete) {
      complete_cut(CutResult{r.mesh, r.complete(), {}}, c, result);
    } else {
      c.done = true;
      result.cut_complete_seconds.push_back(result.cut_step_seconds.back());
    }
  }
}

}  // namespace bemsurg::haptics
