// examples/viewer/action_script.hpp: a session script (tools and timed actions: press, pinch,
// retract, move, release, cut) read from JSON and played back as tool poses over time, so the
// viewer's headless mode replays what a person did with the mouse (docs/design.md §9, "one action
// language"). The format is documented in docs/viewer.md. It is the viewer's reader of the
// session format; when the haptics module ships its own parser, this file becomes a thin adapter
// onto it (ScriptPlayer's interface is all the viewer uses).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace bemsurg::viewer {

/// The tools a person can pick in the GUI (and a script can name).
enum class ToolKind { Point, Sphere, Flat, Pinch, Plate, Cut };

const char* tool_kind_name(ToolKind k);
/// "point", "sphere", "flat", "pinch", "plate" (also "retract"), "cut"; throws SceneError-like
/// bemsurg::InvalidArgumentError naming `where` for anything else.
ToolKind parse_tool_kind(const std::string& text, const std::string& where);

struct ScriptTool {
  std::string name;
  ToolKind kind = ToolKind::Sphere;
  double radius = 0.0;  // sphere, flat, pinch jaw; 0 = the viewer's default for the mesh
  double size = 0.0;    // plate: half-width of the square plate; 0 = default
};

enum class ActionType { Press, Pinch, Retract, Move, Release, Cut };

struct ScriptAction {
  double time = 0.0;
  double duration = 0.0;
  ActionType type = ActionType::Press;
  int tool = 0;  // index into ActionScript::tools
  Eigen::Vector3d at = Eigen::Vector3d::Zero();         // press/pinch/retract: a point on the approach line; cut: from
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ(); // approach (press/pinch/retract) or cut direction (unit)
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();      // translation reached at time + duration
  int steps = 1;                                         // cut: number of increments
};

struct ActionScript {
  std::vector<ScriptTool> tools;
  std::vector<ScriptAction> actions;  // sorted by time
  std::string scene;                  // optional scene path given by the script ("" = none)
  double end_time() const;
};

/// Reads and checks a script; every error is a bemsurg::InvalidArgumentError whose message starts
/// with the file name and the JSON path at fault, e.g. "prod.json: actions[2].depth: expected a
/// non-negative number".
ActionScript load_action_script(const std::string& path);
ActionScript parse_action_script(const std::string& json_text, const std::string& name);

/// Where a scripted tool is at time t: whether it is engaged (button down), the point it engaged
/// at, its approach direction and its translation since engagement.
struct ToolPose {
  bool engaged = false;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

/// A cut increment due at a given time.
struct ScriptCut {
  double time = 0.0;
  int tool = 0;
  int action = 0;  // index of the cut action (a new action opens a new cut)
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
};

class ScriptPlayer {
 public:
  explicit ScriptPlayer(ActionScript script);
  const ActionScript& script() const { return script_; }
  ToolPose pose(int tool, double t) const;
  /// Cut increments with time in (t0, t1].
  std::vector<ScriptCut> cuts_between(double t0, double t1) const;

 private:
  ActionScript script_;
};

}  // namespace bemsurg::viewer
