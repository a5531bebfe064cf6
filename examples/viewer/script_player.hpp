// examples/viewer/script_player.hpp: an action script (docs/actions.md, bemsurg::load_action_script)
// turned into what the viewer's headless mode plays: one scripted haptic device per pressing tool
// (bemsurg::haptics::ScriptedDevice keyframes: tool tip, axis, button), the tool settings of its
// slot, and the cut increments with their times. First contacts of presses and pinches are found
// on the body as it rests under its own weight, as the session does (haptics/session.hpp), so the
// device reports the tool tip in the model frame: a sphere's centre, the point of a point tool or
// pinch, a flat disc's centre, a plate's polygon centroid.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "tool_stepper.hpp"

namespace bemsurg::viewer {

ToolKind tool_kind(ScriptToolShape shape);

/// A cut increment due at `time`; `action` indexes ActionScript::actions (a new action opens a
/// new cut).
struct ScriptCut {
  double time = 0.0;
  int action = 0;
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
};

class ScriptPlayer {
 public:
  /// Throws SceneError when a pressing tool uses a device channel beyond the viewer's kMaxTools.
  explicit ScriptPlayer(ActionScript script);
  const ActionScript& script() const { return script_; }
  /// Tool driven by slot s (-1: none); blades have no slot.
  int tool_of_slot(int slot) const { return tool_of_slot_[static_cast<std::size_t>(slot)]; }
  SlotOptions slot_settings(int tool) const;
  /// The keyframes of a pressing tool's device. `base` is the surface under self-weight (the
  /// table's base state); throws SceneError naming the action whose approach line misses it.
  std::vector<haptics::Keyframe> keyframes(int tool, const TriangleBvh& base) const;
  /// Cut increments with time in (t0, t1].
  std::vector<ScriptCut> cuts_between(double t0, double t1) const;

 private:
  ActionScript script_;
  std::array<int, kMaxTools> tool_of_slot_{};
};

}  // namespace bemsurg::viewer
