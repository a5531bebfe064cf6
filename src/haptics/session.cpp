// Implementation of bemsurg/haptics/session.hpp: action script -> keyframes -> haptic loop, with
// the simulation side (engagements, re-placement, cuts, model hand-over, field) on the caller's
// thread (docs/haptics.md, docs/actions.md).
#include "bemsurg/haptics/session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/presolution/contact_validity.hpp"
#include "session_text.hpp"

namespace bemsurg::haptics {

using detail::centroid;
using detail::describe;

namespace {

/// What turning one tool's actions into keyframes needs besides the actions: the script (for
/// messages), the body, and a contact solver on the base model with this tool added, engaged once
/// per press or pinch off any loop to find where it first touches.
struct KeyframeContext {
  const ActionScript& script;
  const TriangleMesh& mesh;
  ToolContactSolver& probe;
  int probe_tool;
  std::vector<std::string>& warnings;
};

/// Keyframe 0 of a tool: its start, or where its first action begins.
Keyframe start_keyframe(const ScriptTool& tool, const std::vector<const Action*>& actions) {
  Keyframe k;
  k.time = 0.0;
  k.direction = tool.direction;
  if (tool.has_start) {
    k.position = tool.start;
  } else if (!actions.empty()) {
    const Action& a = *actions.front();
    switch (a.type) {
      case ActionType::Move: k.position = a.to; break;
      case ActionType::Press:
      case ActionType::Pinch: k.position = a.at; break;
      case ActionType::Retract: k.position = centroid(tool.polygon); break;
      case ActionType::Cut: k.position = a.from; break;
      case ActionType::Release: break;
    }
  }
  return k;
}

/// The keyframes of one tool, appended action by action (docs/actions.md): each action holds the
/// last pose until its start time, then adds the poses of its motion.
class ToolTrack {
 public:
  ToolTrack(const KeyframeContext& context, const ScriptTool& tool, std::vector<Keyframe>& keyframes, const Keyframe& start)
      : c_(context), tool_(tool), kf_(keyframes), last_contact_(start.position) {
    kf_.push_back(start);
  }

  void add(const Action& a) {
    hold(a.time);
    Keyframe n = kf_.back();
    switch (a.type) {
      case ActionType::Move:
        n.time = a.end_time();
        n.position = a.to;
        kf_.push_back(n);
        break;
      case ActionType::Press: press(a, n); break;
      case ActionType::Pinch:
        n.position = first_contact(a);
        n.direction = a.direction;
        n.buttons |= 1U;
        kf_.push_back(n);
        break;
      case ActionType::Release:
        n.buttons = 0;
        // A pressing tool is lifted 1 mm back from where its last press first touched.
        if (pressed_) n.position = last_contact_ - 1e-3 * n.direction;
        pressed_ = false;
        kf_.push_back(n);
        break;
      case ActionType::Retract: retract(a, n); break;
      case ActionType::Cut: cut(a, n); break;
    }
  }

 private:
  void hold(double time) {
    Keyframe h = kf_.back();
    h.time = std::max(time, kf_.back().time);
    kf_.push_back(h);
  }

  /// Where the tool coming along the action's direction through `at` first touches the body.
  Eigen::Vector3d first_contact(const Action& a) {
    bool met = false;
    try {
      met = c_.probe.engage(c_.probe_tool, a.at, a.direction);
    } catch (const ContactError& e) {  // e.g. a tool wider than the table's region there
      throw ContactError(describe(c_.script, a) + ": " + e.what());
    }
    if (!met)
      throw ContactError(describe(c_.script, a) +
                         ": a tool coming along the direction through `at` does not meet the body "
                         "(or only outside the table's region, or the sphere covers no element centroid)");
    const Eigen::Vector3d o = c_.probe.origin(c_.probe_tool);
    // A tool narrower than a few elements gives a coarse force (docs/stability.md (g)): warned.
    const bool sphere = tool_.shape == ScriptToolShape::Sphere;
    if (sphere || tool_.shape == ScriptToolShape::Flat) {
      RayHit hit;
      const Eigen::Vector3d dir = c_.probe.direction(c_.probe_tool);
      if (c_.probe.base_surface().intersect_ray(o - tool_.radius * dir, dir, hit)) {
        const ToolResolutionCheck res = check_tool_resolution(c_.mesh, hit.element, sphere, tool_.radius, a.depth);
        if (!res.warning.empty()) c_.warnings.push_back(describe(c_.script, a) + ": " + res.warning);
      }
    }
    c_.probe.release(c_.probe_tool);
    return o;
  }

  void press(const Action& a, Keyframe n) {
    // The depth must lie in the model's small-strain range, as for `bemsurg press`
    // (presolution/contact_validity.hpp, docs/robustness.md): refused by action, warned between.
    const bool has_radius = tool_.shape == ScriptToolShape::Flat || tool_.shape == ScriptToolShape::Sphere;
    try {
      const ContactDepthCheck range = check_contact_depth(c_.mesh, a.direction, a.depth, has_radius ? tool_.radius : 0.0);
      if (!range.warning.empty()) c_.warnings.push_back(describe(c_.script, a) + ": " + range.warning);
    } catch (const ContactError& e) { throw ContactError(describe(c_.script, a) + ": " + e.what()); }
    const Eigen::Vector3d p0 = first_contact(a);
    n.position = p0;
    n.direction = a.direction;
    if (tool_.shape == ScriptToolShape::Point) n.buttons |= 1U;  // a point tool engages on the button
    kf_.push_back(n);
    n.time = a.end_time();
    n.position = p0 + a.depth * a.direction;
    kf_.push_back(n);
    last_contact_ = p0;
    pressed_ = true;
  }

  void retract(const Action& a, Keyframe n) {
    // The plate engages at its polygon's centre, then moves by `by` and turns by `rotation`.
    n.position = centroid(tool_.polygon);
    n.direction = tool_.direction;
    n.orientation = Eigen::Quaterniond::Identity();
    n.buttons |= 1U;
    kf_.push_back(n);
    n.time = a.end_time();
    n.position += a.by;
    const double angle = a.rotation.norm();
    n.orientation = angle > 0.0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, a.rotation / angle)) : Eigen::Quaterniond::Identity();
    kf_.push_back(n);
  }

  void cut(const Action& a, Keyframe n) {
    // The blade is held down at `from` for the cut's duration, then lifted.
    n.position = a.from;
    n.direction = a.direction;
    n.buttons |= 1U;
    kf_.push_back(n);
    n.time = a.end_time();
    kf_.push_back(n);
    n.buttons = 0;
    kf_.push_back(n);
  }

  const KeyframeContext& c_;
  const ScriptTool& tool_;
  std::vector<Keyframe>& kf_;
  Eigen::Vector3d last_contact_;
  bool pressed_ = false;
};
}  // namespace

Session::Session(std::shared_ptr<const TriangleMesh> mesh, std::shared_ptr<const GreensTable> table, ActionScript script,
                 SessionOptions options)
    : mesh_(std::move(mesh)),
      table_(std::move(table)),
      script_(std::move(script)),
      options_(std::move(options)),
      felt_(static_cast<int>(script_.tools.size()), options_.loop.max_force, 1.0 / script_.rate_hz) {
  if (!mesh_ || !table_) throw InvalidArgumentError("Session: the mesh or the table is missing");
  if (!(options_.simulation_hz > 0.0) || options_.graphics_hz < 0.0 || !(options_.slide_margin_radii >= 0.0))
    throw InvalidArgumentError("Session: simulation_hz must be positive, graphics_hz and slide_margin_radii non-negative");
  for (std::size_t t = 0; t < script_.tools.size(); ++t)
    if (script_.tools[t].device >= kMaxChannels)
      throw SceneError(script_.path + ": tools[" + std::to_string(t) + "].device: a session drives device channels 0.." +
                       std::to_string(kMaxChannels - 1) + ", got " + std::to_string(script_.tools[t].device));
  if (script_.has_cuts() && !options_.cut_hook) {
    for (std::size_t i = 0; i < script_.actions.size(); ++i)
      if (script_.actions[i].type == ActionType::Cut)
        throw SceneError(describe(script_, script_.actions[i]) +
                         ": cut actions need the cutting module, which is not wired into sessions in this build "
                         "(SessionOptions::cut_hook is unset); remove the cut actions to run the rest");
  }
  const std::size_t n = script_.tools.size();
  engagement_.assign(n, Engagement{});
  position_.assign(n, Eigen::Vector3d::Zero());
  direction_.assign(n, -Eigen::Vector3d::UnitZ());
  last_force_.assign(n, Eigen::Vector3d::Zero());
  have_last_.assign(n, false);
  last_time_.assign(n, 0.0);
  peak_.assign(n, 0.0);
  build_keyframes();
  for (std::size_t t = 0; t < n; ++t) {
    ScriptedDevice probe(keyframes_[t]);
    position_[t] = probe.state_at(0.0).position;
    direction_[t] = probe.state_at(0.0).direction;
  }
  for (std::size_t i = 0; i < script_.actions.size(); ++i) {
    const Action& a = script_.actions[i];
    if (a.type != ActionType::Cut) continue;
    for (int s = 0; s < a.steps; ++s) cuts_.push_back({a.time + s * a.step_interval, static_cast<int>(i), s});
  }
  // Each step cuts the mesh the one before it made: they run one at a time, in time order.
  std::stable_sort(cuts_.begin(), cuts_.end(), [](const ScheduledCut& a, const ScheduledCut& b) { return a.time < b.time; });
  if (!(options_.max_step_s > 0.0)) throw InvalidArgumentError("Session: max_step_s must be positive");
}

Session::~Session() = default;

ToolSpec Session::contact_spec(int tool) const {
  const ScriptTool& t = script_.tools[static_cast<std::size_t>(tool)];
  const ContactMode mode = t.frictionless ? ContactMode::Frictionless : ContactMode::Bonded;
  ToolSpec s;
  switch (t.shape) {
    case ScriptToolShape::Point: s = ToolSpec::point(mode); break;
    case ScriptToolShape::Flat: s = ToolSpec::flat(t.radius, mode); break;
    case ScriptToolShape::Sphere: s = ToolSpec::sphere(t.radius, mode); break;
    case ScriptToolShape::Pinch: s = ToolSpec::pinch(t.radius); break;
    case ScriptToolShape::Plate: s = ToolSpec::plate(t.polygon, t.plate_tolerance, mode); break;
    case ScriptToolShape::Blade: s = ToolSpec::point(); break;  // never engaged: a blade only cuts
  }
  if (t.shape == ScriptToolShape::Sphere || t.shape == ScriptToolShape::Flat) s.slide_margin = options_.slide_margin_radii * t.radius;
  return s;
}

void Session::build_keyframes() {
  // Where presses and pinches first touch: engaged once on the base model, off any loop.
  ToolContactSolver probe(mesh_, table_, 3);
  std::vector<int> ids;
  for (std::size_t t = 0; t < script_.tools.size(); ++t) ids.push_back(probe.add_tool(contact_spec(static_cast<int>(t))));
  keyframes_.assign(script_.tools.size(), {});
  for (std::size_t ti = 0; ti < script_.tools.size(); ++ti) {
    const ScriptTool& tool = script_.tools[ti];
    std::vector<const Action*> mine;
    for (const Action& a : script_.actions)
      if (a.tool == static_cast<int>(ti)) mine.push_back(&a);
    const KeyframeContext context{script_, *mesh_, probe, ids[ti], warnings_};
    ToolTrack track(context, tool, keyframes_[ti], start_keyframe(tool, mine));
    for (const Action* a : mine) track.add(*a);
  }
}

bool Session::engage_or_wait(ToolContactSolver& s, int tool, const Eigen::Vector3d& at, const Eigen::Vector3d& direction) const {
  // True when engaged, or when the engagement waits for a cut step's complete table; false: it missed.
  try {
    return s.engage(tool, at, direction) || completing_;
  } catch (const ContactError&) {
    if (!completing_) throw;  // outside the region of a complete table: the scene's error, as before
    return true;
  }
}

std::unique_ptr<ContactModel> Session::build_model() {
  auto m = std::make_unique<ContactModel>();
  m->mesh = mesh_;
  m->table = table_;
  m->solver = std::make_unique<ToolContactSolver>(mesh_, table_, script_.capacity_rows);
  m->version = next_version_++;
  ToolContactSolver& s = *m->solver;
  for (std::size_t ti = 0; ti < script_.tools.size(); ++ti) {
    const int t = s.add_tool(contact_spec(static_cast<int>(ti)));
    const ScriptTool& tool = script_.tools[ti];
    const auto ch = static_cast<std::size_t>(tool.device);
    Engagement& e = engagement_[ti];
    m->engaged_orientation[ch] = e.orientation;
    if (tool.shape == ScriptToolShape::Blade) continue;
    m->tool_of_channel[ch] = t;
    switch (tool.shape) {
      case ScriptToolShape::Sphere:
      case ScriptToolShape::Flat:
        if (e.placed) s.place(t, e.at, e.direction);
        break;
      // Missed the body: nothing held. Not while a cut step completes: the first response's table
      // covers only the tools' reach (engage refuses an element outside it), and the complete table
      // (a rebuild follows) decides.
      case ScriptToolShape::Point:
      case ScriptToolShape::Pinch:
        if (e.active && !engage_or_wait(s, t, e.at, e.direction)) e.active = false;
        break;
      case ScriptToolShape::Plate:
        if (e.active && !engage_or_wait(s, t, centroid(tool.polygon), tool.direction)) e.active = false;
        break;
      case ScriptToolShape::Blade: break;
    }
    if (s.engaged(t)) s.set_translation(t, position_[ti] - s.origin(t));
  }
  s.update();  // throws CapacityError naming the rows needed: the script's capacity_rows is too small
  tables_[m->version] = table_;
  return m;
}

void Session::drain(HapticLoop& loop, SessionObserver* observer) {
  TickSample sample;
  while (loop.pop_sample(sample)) {
    if (observer) observer->on_sample(sample);
    for (std::size_t t = 0; t < script_.tools.size(); ++t) {
      const ChannelSample& c = sample.channel[static_cast<std::size_t>(script_.tools[t].device)];
      position_[t] = c.position;
      direction_[t] = c.direction;
      const Eigen::Vector3d& f = c.model_force;
      const double mag = f.norm();
      peak_[t] = std::max(peak_[t], mag);
      if (have_last_[t]) {
        const double prev = last_force_[t].norm();
        const double big = std::max(mag, prev);
        if (big > 0.0) {
          // Per loop period, as the felt figures (felt_force.hpp): a late tick's change is shared
          // over the periods it spans.
          const double spans = FeltForceRecorder::periods_spanned(sample.time - last_time_[t], 1.0 / script_.rate_hz);
          jumps_.emplace_back((f - last_force_[t]).norm() / big / spans, std::min(mag, prev));
          jump_tool_.push_back(static_cast<int>(t));
          jump_time_.push_back(sample.time);
        }
      }
      felt_.add(static_cast<int>(t), sample.time, f, c.force);
      last_force_[t] = f;
      last_time_[t] = sample.time;
      have_last_[t] = true;
    }
  }
}

void Session::simulation_step(HapticLoop& loop, SessionObserver* observer, SessionResult& result) {
  const double now = loop.time();
  drain(loop, observer);
  ButtonEvent e;
  while (loop.pop_event(e)) {
    if (e.button != 0) continue;
    for (std::size_t t = 0; t < script_.tools.size(); ++t) {
      const ScriptTool& tool = script_.tools[t];
      if (tool.device != e.channel) continue;
      if (tool.shape == ScriptToolShape::Point || tool.shape == ScriptToolShape::Pinch || tool.shape == ScriptToolShape::Plate) {
        Engagement& g = engagement_[t];
        g.active = e.down;
        g.at = e.position;
        g.direction = e.direction;
        g.orientation = e.orientation;
        dirty_ = true;
      }
    }
  }
  // Sliding tools: placed again (on a new model) when they near the edge of their candidates.
  for (std::size_t t = 0; t < script_.tools.size(); ++t) {
    const ScriptTool& tool = script_.tools[t];
    if (tool.shape != ScriptToolShape::Sphere && tool.shape != ScriptToolShape::Flat) continue;
    Engagement& g = engagement_[t];
    const Eigen::Vector3d d = position_[t] - g.at;
    const double lateral = (d - d.dot(g.direction) * g.direction).norm();
    if (!g.placed || lateral > 0.5 * options_.slide_margin_radii * tool.radius) {
      g.placed = true;
      g.at = position_[t];
      g.direction = direction_[t];
      dirty_ = true;
    }
  }
  if (options_.first_response && !cut_task_.busy()) {  // what the tools hold now, for a cut step's first response
    in_contact_.clear();
    if (const PublishedContact* pc = loop.latest_contact())
      in_contact_.assign(pc->elements.begin(),
                         pc->elements.begin() + std::min<std::ptrdiff_t>(pc->count, std::ptrdiff_t(pc->elements.size())));
  }
  run_cuts(now, observer, result);
  if (dirty_ && !loop.offer_pending()) {
    std::unique_ptr<ContactModel> m = build_model();
    if (loop.offer(m)) {
      ++result.models_built;
      dirty_ = false;
    }
  }
  while (loop.take_retired()) {}
  const std::uint64_t rendered = loop.model_version();
  for (auto it = tables_.begin(); it != tables_.end() && it->first + 2 < rendered;) it = tables_.erase(it);
  // "Alive": beaten while a cut step computes in the background, not when a step is hung.
  if (!hung_) loop.heartbeat();
  if (options_.graphics_hz > 0.0 && now >= next_graphics_) {
    next_graphics_ = now + 1.0 / options_.graphics_hz;
    if (const PublishedContact* pc = loop.latest_contact()) {
      const auto it = tables_.find(pc->model_version);
      if (it != tables_.end()) {
        const auto t0 = std::chrono::steady_clock::now();
        if (field_.size() != it->second->num_dofs()) field_.resize(it->second->num_dofs());
        it->second->displacement_field(pc->elements.data(), pc->tractions.data(), pc->count, field_);
        field_ms_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        ++result.field_updates;
      }
    }
  }
}

void Session::finish_metrics(SessionResult& result) const {
  // The jump of the model force, and what the hand feels (felt_force.hpp), each over ticks whose
  // model force is at least 10 % of the tool's peak (docs/haptics.md, "Force continuity").
  for (std::size_t i = 0; i < jumps_.size(); ++i) {
    const double threshold = 0.1 * peak_[static_cast<std::size_t>(jump_tool_[i])];
    if (jumps_[i].second >= threshold && threshold > 0.0 && jumps_[i].first > result.max_force_jump_fraction) {
      result.max_force_jump_fraction = jumps_[i].first;
      result.max_force_jump_time = jump_time_[i];
      result.max_force_jump_tool = jump_tool_[i];
    }
  }
  result.felt = felt_.result();
}

SessionResult Session::run(SessionObserver* observer) {
  SessionResult result;
  std::vector<std::unique_ptr<HapticDevice>> owned;
  int channels = 1;
  for (const ScriptTool& t : script_.tools) channels = std::max(channels, t.device + 1);
  std::vector<HapticDevice*> devices(static_cast<std::size_t>(channels), nullptr);
  for (std::size_t t = 0; t < script_.tools.size(); ++t) {
    owned.push_back(std::make_unique<ScriptedDevice>(keyframes_[t], "scripted " + script_.tools[t].name, options_.loop.max_force));
    devices[static_cast<std::size_t>(script_.tools[t].device)] = owned.back().get();
  }
  for (auto& d : devices)
    if (!d) {
      owned.push_back(std::make_unique<NullDevice>(options_.loop.max_force));
      d = owned.back().get();
    }
  HapticLoopOptions ls = options_.loop;
  ls.rate_hz = script_.rate_hz;
  if (script_.has_cuts() && options_.cut_prepare) options_.cut_prepare(table_);  // before the clock starts
  HapticLoop loop(ls, devices);
  const auto wall0 = std::chrono::steady_clock::now();
  simulation_step(loop, observer, result);  // the first model is waiting before the first tick
  if (options_.virtual_clock) {
    const auto ticks = static_cast<long>(std::ceil(script_.duration * script_.rate_hz));
    const long every = std::max(1L, std::lround(script_.rate_hz / options_.simulation_hz));
    for (long i = 0; i <= ticks; ++i) {
      loop.tick(double(i) / script_.rate_hz);
      if (i % every == 0) simulation_step(loop, observer, result);
    }
  } else {
    // Background work leaves the haptic thread a core while the loop runs.
    const BackgroundThreadBudget budget(options_.limit_background_threads);
    thread_budget_ = budget.threads();
    in_realtime_ = true;
    loop.start();
    try {
      const auto period = std::chrono::duration<double>(1.0 / options_.simulation_hz);
      // Until the script's end, and until every cut due by then has been applied (a slow cut
      // must not be skipped; the loop renders the old model meanwhile).
      auto cuts_pending = [&] { return std::any_of(cuts_.begin(), cuts_.end(), [](const ScheduledCut& c) { return !c.done; }); };
      while (loop.time() < script_.duration || cuts_pending()) {
        simulation_step(loop, observer, result);
        if (hung_ && loop.time() - hung_since_ > options_.loop.stale_after_s + options_.loop.ramp_s)
          throw Error("session: a cut step has run for more than " + number_text(options_.max_step_s) +
                      " s (SessionOptions::max_step_s): the simulation side is taken as hung and the force was faded to zero");
        std::this_thread::sleep_for(period);
        if (std::chrono::steady_clock::now() - wall0 > std::chrono::duration<double>(4.0 * script_.duration + 30.0 + options_.max_step_s))
          throw Error("session: the haptic loop stopped advancing (session time " + number_text(loop.time()) + " s)");
      }
    } catch (...) {
      in_realtime_ = false;
      loop.stop();  // zero force before the error leaves
      throw;
    }
    in_realtime_ = false;
    loop.stop();
  }
  drain(loop, observer);
  result.session_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  result.loop = loop.statistics();
  result.peak_force = peak_;
  finish_metrics(result);
  if (!field_ms_.empty()) {
    std::vector<double> v = field_ms_;
    std::sort(v.begin(), v.end());
    auto q = [&](double p) { return v[static_cast<std::size_t>(p * double(v.size() - 1))]; };
    result.field_ms = {q(0.5), q(0.99), q(0.999), v.back()};
  }
  return result;
}

}  // namespace bemsurg::haptics
