// bemsurg/haptics/session.hpp: a scripted surgical session (docs/actions.md, docs/haptics.md) —
// the action script becomes keyframes of scripted devices (one per tool channel), the haptic loop
// renders their forces from the contact model, and the simulation side (this object, on the
// calling thread) turns button edges into engagements, re-places sliding tools, runs cuts, builds
// new contact models and hands them to the loop whole, and computes the displacement field at the
// graphics rate from the contact the loop publishes. `bemsurg session`, the benchmark and the
// viewer's headless mode all run sessions through this class.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bemsurg/haptics/action_script.hpp"
#include "bemsurg/haptics/background_task.hpp"
#include "bemsurg/haptics/felt_force.hpp"
#include "bemsurg/haptics/haptic_loop.hpp"
#include "bemsurg/haptics/scripted_device.hpp"

namespace bemsurg::haptics {

/// One cut increment to compute (docs/design.md §7): on the current snapshots, from the surface
/// point nearest `from` along `direction`; `step` counts from 0 within the action.
/// \ingroup haptics
struct CutRequest {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
  int step = 0;
  int action = 0;  // index into ActionScript::actions
  /// A first response is wanted (reach > 0; real-time sessions with background steps): the table may
  /// first cover only the region elements within `reach` of these points (the tools, and the elements in
  /// contact), and CutResult::complete then makes the whole one.
  std::vector<Eigen::Vector3d> tools = {};
  double reach = 0.0;
};
/// The new snapshots after the cut (new objects: the old ones stay valid for whoever holds them).
/// \ingroup haptics
struct CutResult {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  /// Set when `table` is a first response (docs/cutting.md, "First response"): computes the complete
  /// table of the same step. The session calls it once, before the next cut step, off the haptic thread.
  std::function<std::shared_ptr<const GreensTable>()> complete = nullptr;
};
/// The cutting module's entry point for sessions. Unset: a session refuses scripts with cuts.
using CutHook = std::function<CutResult(const CutRequest&)>;
/// Makes ready what the cut hook's first steps will need, for the session's table (e.g. touched storage
/// for their tables: docs/cutting.md, "Snapshot storage"). A session whose script cuts calls it once,
/// before its clock starts.
using CutPrepare = std::function<void(const std::shared_ptr<const GreensTable>&)>;

/// How a Session runs: virtual or real-time clock, the simulation and graphics rates, how far sphere and flat tools may slide,
/// the haptic loop's options and the hook that computes cuts.
/// \ingroup haptics
struct SessionOptions {
  /// true: ticks run back to back in session time on the calling thread, the simulation side
  /// every few ticks — deterministic (tests, reproducible traces); false: the loop's own thread
  /// in real time.
  bool virtual_clock = false;
  double simulation_hz = 250.0;  // events, re-placement, cuts, trace draining
  double graphics_hz = 60.0;     // field from the published contact (0: not computed)
  /// Sphere and flat tools may slide this many radii sideways before they are placed again.
  double slide_margin_radii = 1.0;
  HapticLoopOptions loop;  // rate_hz is taken from the script
  CutHook cut_hook;
  /// Called once before the clock starts when the script cuts (unset: nothing to make ready).
  CutPrepare cut_prepare;
  /// Real-time sessions: a cut step runs on a background thread (BackgroundTask) while the
  /// simulation side keeps beating the heartbeat and the loop renders the old model; false: on the
  /// simulation thread, which then stops beating while it computes (the behaviour before 0.4, kept
  /// for the before/after benchmark; the watchdog fades the force during any step longer than
  /// loop.stale_after_s). Virtual-clock sessions always compute steps in line (deterministic).
  bool background_steps = true;
  /// Real-time sessions: background work gets cores - 1 threads while the loop runs
  /// (BackgroundThreadBudget), so the haptic thread keeps a core.
  bool limit_background_threads = true;
  /// Cut steps answer in two phases (docs/haptics.md, "Feeling through a cut"): first the table columns
  /// of the elements within reach of the tools (each tool's radius times 1 + slide_margin_radii, plus
  /// reach_margin, from where it is when the step is requested), handed to the loop at once; then the
  /// complete table, before the next cut step starts. false: one phase (the complete table only).
  bool first_response = true;
  /// How far a tool may move while a step completes, beyond its own reach (m).
  double reach_margin = 0.01;
  /// A background step running longer than this is taken as hung: the heartbeat stops (the
  /// watchdog fades the force within loop.stale_after_s + loop.ramp_s) and the session ends with
  /// an error.
  double max_step_s = 20.0;

  /// The first response's reach rule for one tool: how far from its tip (or from an element it
  /// touches) it can act before a cut step completes: radius x (1 + slide_margin_radii) +
  /// reach_margin, a plate's `plate_size` (its polygon's tolerance or extent) + reach_margin, and
  /// never less than reach_margin. Sessions, the viewer and bench_cut_continuity share it.
  double tool_reach(double radius, double plate_size = 0.0) const {
    return std::max({reach_margin, radius * (1.0 + slide_margin_radii) + reach_margin, plate_size + reach_margin});
  }
};

/// Receives what the session produces, on the simulation side's thread.
/// \ingroup haptics
class SessionObserver {
 public:
  virtual ~SessionObserver() = default;
  virtual void on_sample(const TickSample&) {}
  /// After cut number `index` (from 1) was applied: the new mesh.
  virtual void on_cut(int /*index*/, const TriangleMesh&) {}
};

/// What Session::run reports: the loop's statistics, the largest force jump between ticks, peak forces per tool, the models
/// built, cuts, displacement-field updates and their times.
/// \ingroup haptics
struct SessionResult {
  LoopStatistics loop;
  /// Largest |F_k - F_(k-1)| / max(|F_k|, |F_(k-1)|) of a tool's contact-model force between
  /// consecutive ticks, over pairs where both magnitudes are at least 10 % of that tool's peak;
  /// per loop period (a late tick's change divided by the periods its gap spans, felt_force.hpp).
  double max_force_jump_fraction = 0.0;
  double max_force_jump_time = 0.0;  // session time of that jump (s)
  int max_force_jump_tool = -1;
  /// What a hand feels (felt_force.hpp): the smallest delivered / model ratio and the largest
  /// tick-to-tick change of the delivered force, over ticks whose model force is at least 10 % of
  /// the tool's peak.
  FeltForce felt;
  std::vector<double> peak_force;  // per tool, N (model force)
  int models_built = 0;
  int cuts = 0;
  /// Wall time of each cut step from its request to its first response delivered to the loop (the complete
  /// table, without first responses), in order.
  std::vector<double> cut_step_seconds;
  /// Wall time of each cut step from its request to its complete table delivered to the loop, in order.
  std::vector<double> cut_complete_seconds;
  /// Cut steps whose time came while the step before was still being computed (either phase): they waited for it.
  int cut_steps_waited = 0;
  int field_updates = 0;
  Percentiles field_ms;  // time of one displacement-field update (graphics side), in ms
  double session_seconds = 0.0;
};

/// A scripted surgical session (docs/actions.md, docs/haptics.md): the action script drives scripted devices, the haptic loop
/// renders their forces, and this object, on the calling thread, runs engagements and cuts and hands new contact models to the loop.
/// \ingroup haptics
class Session {
 public:
  /// Checks the script against the model (tools on channels 0..3, no cut without a hook: the
  /// error names the first cut action) and resolves where presses and pinches first touch the
  /// surface into keyframes. Throws SceneError / ContactError with the action at fault.
  Session(std::shared_ptr<const TriangleMesh> mesh, std::shared_ptr<const GreensTable> table, ActionScript script,
          SessionOptions options = {});
  ~Session();

  /// Runs the whole script; the loop's devices get zero force at the start and the end.
  SessionResult run(SessionObserver* observer = nullptr);

  const ActionScript& script() const { return script_; }
  /// Presses deeper than the small-strain warning thresholds (contact_validity.hpp), one line each
  /// naming the action; presses beyond the refusal thresholds make the constructor throw.
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::vector<Keyframe>& keyframes(int tool) const { return keyframes_[static_cast<std::size_t>(tool)]; }
  /// The device channel of each tool.
  int channel_of(int tool) const { return script_.tools[static_cast<std::size_t>(tool)].device; }

 private:
  struct Engagement {
    bool active = false;
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    bool placed = false;  // sphere / flat: placed at `at`
  };
  struct ScheduledCut {
    double time;
    int action;
    int step;
    bool done = false;
    bool waited = false;  // its time came while the step before was still completing
  };
  ToolSpec contact_spec(int tool) const;
  void build_keyframes();
  void simulation_step(HapticLoop& loop, SessionObserver* observer, SessionResult& result);
  std::unique_ptr<ContactModel> build_model();
  void drain(HapticLoop& loop, SessionObserver* observer);
  void run_cuts(double now, SessionObserver* observer, SessionResult& result);
  void apply_cut(const CutResult& r, const ScheduledCut& c, SessionObserver* observer, SessionResult& result);
  void complete_cut(const CutResult& r, ScheduledCut& c, SessionResult& result);
  std::vector<Eigen::Vector3d> reach_points(double& reach) const;
  bool engage_or_wait(ToolContactSolver& s, int tool, const Eigen::Vector3d& at, const Eigen::Vector3d& direction) const;
  void finish_metrics(SessionResult& result) const;

  std::shared_ptr<const TriangleMesh> mesh_;
  std::shared_ptr<const GreensTable> table_;
  ActionScript script_;
  SessionOptions options_;
  std::vector<std::vector<Keyframe>> keyframes_;
  std::vector<std::string> warnings_;
  std::vector<Engagement> engagement_;
  std::vector<ScheduledCut> cuts_;  // in time order
  BackgroundTask<CutResult> cut_task_;
  std::size_t cut_in_flight_ = 0;  // index into cuts_ of the step cut_task_ computes
  double cut_started_ = 0.0;       // wall seconds of the step in line
  bool completing_ = false;        // cut_task_ computes the complete table of the step in flight
  std::vector<Index> in_contact_;  // elements in contact when the last cut step was requested
  std::chrono::steady_clock::time_point cut_requested_{};
  bool in_realtime_ = false;
  int thread_budget_ = 0;  // OpenMP threads for a background step (0: unchanged)
  bool hung_ = false;
  double hung_since_ = 0.0;
  std::vector<Eigen::Vector3d> position_;  // latest device position per tool (model frame)
  std::vector<Eigen::Vector3d> direction_;
  std::uint64_t next_version_ = 1;
  bool dirty_ = true;
  std::map<std::uint64_t, std::shared_ptr<const GreensTable>> tables_;  // by model version (graphics)
  // continuity tracking
  std::vector<Eigen::Vector3d> last_force_;
  std::vector<double> last_time_;  // session time of each tool's previous sample
  std::vector<bool> have_last_;
  std::vector<std::pair<double, double>> jumps_;  // (jump fraction, smaller magnitude) per tool pair
  std::vector<double> jump_time_;
  std::vector<int> jump_tool_;
  FeltForceRecorder felt_;
  std::vector<double> peak_;
  double next_graphics_ = 0.0;
  Eigen::VectorXd field_;
  std::vector<double> field_ms_;
};

}  // namespace bemsurg::haptics
