// bemsurg/haptics/action_script.hpp: the one action language of a surgical session (docs/design.md §9
// "one action language"; Wang et al. 2007 §6: prodding, pinching, retracting and cutting with a
// PHANToM). A script names its tools and lists timed actions — move, press, pinch, release,
// retract, cut — so the same file drives the scripted haptic device, `bemsurg session` and the
// viewer's headless mode, and every interactive behaviour can be replayed and tested.
//
// The format is specified key by key in docs/actions.md; bemsurg/io/action_script.hpp reads it
// (JSON, in bemsurg::bemsurg). This header holds the parsed script as plain data (Eigen vectors, SI units, model frame); it does not know the model: where a press
// first touches the surface is found by the session against the deformed surface.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace bemsurg {

/// Tool shapes of a session (contact_tools.hpp for the contact models; a blade only cuts).
/// \ingroup haptics
enum class ScriptToolShape { Point, Flat, Sphere, Pinch, Plate, Blade };

/// "point", "flat", ... as written in scripts.
const char* to_string(ScriptToolShape shape);

/// One tool of an action script (docs/actions.md): its name, shape and size, contact model (frictionless or bonded),
/// axis, the device channel that drives it, and its start position.
/// \ingroup haptics
struct ScriptTool {
  std::string name;
  ScriptToolShape shape = ScriptToolShape::Sphere;
  /// flat: disc radius; sphere: sphere radius; pinch: jaw radius (0: the element hit only).
  double radius = 0.0;
  /// Frictionless contact (normal component only) or bonded. Defaults: sphere and flat
  /// frictionless; point, pinch and plate bonded (a pinch is always bonded).
  bool frictionless = false;
  /// The tool's axis (unit): the approach direction of a press, the plate's normal. Default -z.
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  /// plate: polygon in the model frame where the retraction engages (>= 3 vertices, planar).
  std::vector<Eigen::Vector3d> polygon;
  /// plate: elements whose centroid lies within this distance of the plate's plane are held.
  double plate_tolerance = 0.0;
  /// Which device channel drives the tool (0, 1, ...): two tools on two channels are two hands.
  int device = 0;
  /// Where the tool tip is before its first action (model frame). Default: where its first action
  /// starts (a move's `to`, a press's or pinch's `at`, a plate's polygon centroid, a cut's `from`).
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  bool has_start = false;
};

/// The kind of one action of a script: move, press, pinch, release, retract or cut.
/// \ingroup haptics
enum class ActionType { Move, Press, Pinch, Release, Retract, Cut };

/// "move", "press", ... as written in scripts.
const char* to_string(ActionType type);

/// One timed action. Which fields are meaningful depends on `type` (docs/actions.md):
///   move     to, duration                  the tool tip moves in a straight line to `to`
///   press    at, direction, depth, duration  approach along `direction` through `at` to first
///                                          contact, then push `depth` beyond it over `duration`
///   pinch    at, direction                 the jaws close on the surface point hit first
///   release  -                             open the pinch / let go of the plate / lift a tool
///   retract  by, rotation, duration        the tool's plate engages and is moved by `by` (and
///                                          turned by the small rotation vector `rotation`)
///   cut      from, direction, steps, step_interval   the blade cuts from the surface point
///                                          nearest `from` along `direction`, `steps` increments
/// \ingroup haptics
struct Action {
  double time = 0.0;      // seconds from the session start
  double duration = 0.0;  // seconds; 0 = at once
  int tool = 0;           // index into ActionScript::tools
  ActionType type = ActionType::Move;
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();  // unit
  double depth = 0.0;
  Eigen::Vector3d by = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
  int steps = 1;
  double step_interval = 0.1;  // seconds between cut increments
  /// When the action is over: time + duration (cut: time + (steps - 1) * step_interval).
  double end_time() const;
};

/// A parsed action script (docs/actions.md) as plain data: its tools, timed actions sorted by time, haptic rate and
/// session length, driving the scripted device, `bemsurg session` and the viewer's headless mode alike.
/// \ingroup haptics
struct ActionScript {
  int version = 1;
  /// Scene file named by the script (resolved against the script's directory), or empty. The
  /// command line's SCENE.json, when given, takes precedence.
  std::string scene;
  double rate_hz = 1000.0;  // haptic loop rate, 100 .. 10000
  /// Session length in seconds: the given value, or the last action's end plus 0.1 s.
  double duration = 0.0;
  /// The most contact constraint rows of all tools together (bonded elements take 3).
  int capacity_rows = 300;
  std::vector<ScriptTool> tools;
  /// Sorted by time (stable: equal times keep file order).
  std::vector<Action> actions;
  /// Unknown keys (ignored) and other things probably unintended.
  std::vector<std::string> warnings;
  /// The script file as given (for messages) and the directory relative paths resolve against.
  std::string path;
  std::string directory;

  int tool_index(const std::string& name) const;  // -1 when absent
  bool has_cuts() const;
};

}  // namespace bemsurg
