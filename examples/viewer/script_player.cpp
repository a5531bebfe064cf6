// examples/viewer/script_player.cpp: action scripts as scripted devices (see script_player.hpp).
#include "script_player.hpp"

#include <algorithm>

#include "bemsurg/error.hpp"

namespace bemsurg::viewer {

ToolKind tool_kind(ScriptToolShape shape) {
  switch (shape) {
    case ScriptToolShape::Point: return ToolKind::Point;
    case ScriptToolShape::Flat: return ToolKind::Flat;
    case ScriptToolShape::Sphere: return ToolKind::Sphere;
    case ScriptToolShape::Pinch: return ToolKind::Pinch;
    case ScriptToolShape::Plate: return ToolKind::Plate;
    case ScriptToolShape::Blade: return ToolKind::Cut;
  }
  return ToolKind::Point;
}

ScriptPlayer::ScriptPlayer(ActionScript script) : script_(std::move(script)) {
  tool_of_slot_.fill(-1);
  for (std::size_t i = 0; i < script_.tools.size(); ++i) {
    const ScriptTool& t = script_.tools[i];
    if (t.shape == ScriptToolShape::Blade) continue;
    if (t.device < 0 || t.device >= kMaxTools)
      throw SceneError(script_.path + ": tools[" + std::to_string(i) + "].device: the viewer drives " + std::to_string(kMaxTools) +
                       " tools at once (channels 0 and 1); tool '" + t.name + "' is on channel " + std::to_string(t.device));
    int& slot = tool_of_slot_[static_cast<std::size_t>(t.device)];
    if (slot >= 0)
      throw SceneError(script_.path + ": tools[" + std::to_string(i) + "].device: channel " + std::to_string(t.device) +
                       " already drives tool '" + script_.tools[static_cast<std::size_t>(slot)].name + "'");
    slot = static_cast<int>(i);
  }
}

SlotOptions ScriptPlayer::slot_settings(int tool) const {
  const ScriptTool& t = script_.tools[static_cast<std::size_t>(tool)];
  SlotOptions s;
  s.kind = tool_kind(t.shape);
  s.radius = t.radius;
  s.frictionless = t.frictionless;
  s.frictionless_given = true;
  s.polygon = t.polygon;
  s.plate_tolerance = t.plate_tolerance;
  return s;
}

std::vector<haptics::Keyframe> ScriptPlayer::keyframes(int tool, const TriangleBvh& base) const {
  const ScriptTool& t = script_.tools[static_cast<std::size_t>(tool)];
  std::vector<haptics::Keyframe> k;
  Eigen::Vector3d pos = t.has_start ? t.start : Eigen::Vector3d::Zero();
  Eigen::Vector3d dir = t.direction;
  std::uint32_t button = 0;
  bool have_pos = t.has_start;
  auto key = [&](double time) {
    haptics::Keyframe f;
    f.time = time;
    f.position = pos;
    f.direction = dir;
    f.buttons = button;
    k.push_back(f);
  };
  // First contact along the approach line through `at` (the tip where the tool meets the surface).
  auto contact_tip = [&](const Action& a, std::size_t index) {
    RayHit hit;
    const Eigen::Vector3d d = a.direction;
    const double L = 1e3;  // metres: far beyond any model
    if (!base.intersect_ray(a.at - L * d, d, hit, 2.0 * L, true))
      throw SceneError(script_.path + ": actions[" + std::to_string(index) + "] (" + to_string(a.type) + " of '" + t.name +
                       "'): the approach line through 'at' along 'direction' misses the body");
    return t.shape == ScriptToolShape::Sphere ? Eigen::Vector3d(hit.point - t.radius * d) : hit.point;
  };
  for (std::size_t i = 0; i < script_.actions.size(); ++i) {
    const Action& a = script_.actions[i];
    if (a.tool != tool) continue;
    if (!have_pos) {  // the tool waits where its first action starts
      pos = a.type == ActionType::Move ? a.to : a.at;
      if (a.type == ActionType::Retract && !t.polygon.empty()) {
        pos.setZero();
        for (const auto& p : t.polygon) pos += p;
        pos /= double(t.polygon.size());
      }
      have_pos = true;
      key(0.0);
    }
    switch (a.type) {
      case ActionType::Press: {
        key(a.time);
        dir = a.direction;
        pos = contact_tip(a, i);
        button = 1;
        key(a.time);
        pos += a.depth * dir;
        key(a.time + a.duration);
        break;
      }
      case ActionType::Pinch:
        key(a.time);
        dir = a.direction;
        pos = contact_tip(a, i);
        button = 1;
        key(a.time);
        break;
      case ActionType::Move:
        key(a.time);
        pos = a.to;
        key(a.time + a.duration);
        break;
      case ActionType::Release:
        key(a.time);
        button = 0;
        key(a.time);
        break;
      case ActionType::Retract: {
        key(a.time);
        if (!t.polygon.empty()) {
          pos.setZero();
          for (const auto& p : t.polygon) pos += p;
          pos /= double(t.polygon.size());
        }
        dir = t.direction;
        button = 1;
        key(a.time);
        pos += a.by;  // the rotation of a retract is not played by the viewer (docs/viewer.md)
        key(a.time + a.duration);
        break;
      }
      case ActionType::Cut: break;
    }
  }
  if (k.empty()) key(0.0);
  return k;
}

std::vector<ScriptCut> ScriptPlayer::cuts_between(double t0, double t1) const {
  std::vector<ScriptCut> out;
  for (std::size_t i = 0; i < script_.actions.size(); ++i) {
    const Action& a = script_.actions[i];
    if (a.type != ActionType::Cut) continue;
    for (int s = 0; s < a.steps; ++s) {
      const double time = a.time + s * a.step_interval;
      if (time > t0 && time <= t1) out.push_back({time, static_cast<int>(i), a.from, a.direction});
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const ScriptCut& x, const ScriptCut& y) { return x.time < y.time; });
  return out;
}

}  // namespace bemsurg::viewer
