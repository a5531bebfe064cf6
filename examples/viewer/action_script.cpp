// examples/viewer/action_script.cpp: reading and playing session scripts (see action_script.hpp).
#include "action_script.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bemsurg/error.hpp"

namespace bemsurg::viewer {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& name, const std::string& where, const std::string& what) {
  throw InvalidArgumentError(name + ": " + where + ": " + what);
}

double number(const json& j, const std::string& name, const std::string& where, bool non_negative) {
  if (!j.is_number()) fail(name, where, std::string("expected a number, got ") + j.type_name());
  const double v = j.get<double>();
  if (!std::isfinite(v)) fail(name, where, "expected a finite number");
  if (non_negative && v < 0.0) fail(name, where, "expected a non-negative number, got " + std::to_string(v));
  return v;
}

Eigen::Vector3d vec3(const json& j, const std::string& name, const std::string& where) {
  if (!j.is_array() || j.size() != 3) fail(name, where, "expected an array of three numbers");
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) v(k) = number(j[static_cast<std::size_t>(k)], name, where + "[" + std::to_string(k) + "]", false);
  return v;
}

Eigen::Vector3d unit3(const json& j, const std::string& name, const std::string& where) {
  const Eigen::Vector3d v = vec3(j, name, where);
  const double n = v.norm();
  if (!(n > 0.0) || !std::isfinite(n)) fail(name, where, "expected a nonzero direction");
  return v / n;
}

const json& required(const json& obj, const char* key, const std::string& name, const std::string& where) {
  auto it = obj.find(key);
  if (it == obj.end()) fail(name, where, std::string("missing key \"") + key + "\"");
  return *it;
}

}  // namespace

const char* tool_kind_name(ToolKind k) {
  switch (k) {
    case ToolKind::Point: return "point";
    case ToolKind::Sphere: return "sphere";
    case ToolKind::Flat: return "flat";
    case ToolKind::Pinch: return "pinch";
    case ToolKind::Plate: return "plate";
    case ToolKind::Cut: return "cut";
  }
  return "?";
}

ToolKind parse_tool_kind(const std::string& t, const std::string& where) {
  if (t == "point") return ToolKind::Point;
  if (t == "sphere") return ToolKind::Sphere;
  if (t == "flat") return ToolKind::Flat;
  if (t == "pinch") return ToolKind::Pinch;
  if (t == "plate" || t == "retract" || t == "retractor") return ToolKind::Plate;
  if (t == "cut" || t == "scalpel") return ToolKind::Cut;
  throw InvalidArgumentError(where + ": unknown tool type '" + t + "' (point, sphere, flat, pinch, plate, cut)");
}

double ActionScript::end_time() const {
  double t = 0.0;
  for (const auto& a : actions) t = std::max(t, a.time + a.duration);
  return t;
}

ActionScript load_action_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidArgumentError(path + ": cannot open the action script");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_action_script(ss.str(), path);
}

ActionScript parse_action_script(const std::string& text, const std::string& name) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InvalidArgumentError(name + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) fail(name, "(top level)", "expected an object with \"tools\" and \"actions\"");
  ActionScript s;
  if (auto it = root.find("scene"); it != root.end()) {
    if (!it->is_string()) fail(name, "scene", "expected a file name");
    s.scene = it->get<std::string>();
  }
  const json& tools = required(root, "tools", name, "(top level)");
  if (!tools.is_array() || tools.empty()) fail(name, "tools", "expected a non-empty array");
  for (std::size_t i = 0; i < tools.size(); ++i) {
    const std::string w = "tools[" + std::to_string(i) + "]";
    const json& t = tools[i];
    if (!t.is_object()) fail(name, w, "expected an object");
    ScriptTool tool;
    const json& nm = required(t, "name", name, w);
    if (!nm.is_string()) fail(name, w + ".name", "expected a string");
    tool.name = nm.get<std::string>();
    for (const auto& other : s.tools)
      if (other.name == tool.name) fail(name, w + ".name", "duplicate tool name '" + tool.name + "'");
    const json& ty = required(t, "type", name, w);
    if (!ty.is_string()) fail(name, w + ".type", "expected a string");
    tool.kind = parse_tool_kind(ty.get<std::string>(), name + ": " + w + ".type");
    if (auto it = t.find("radius"); it != t.end()) tool.radius = number(*it, name, w + ".radius", true);
    if (auto it = t.find("size"); it != t.end()) tool.size = number(*it, name, w + ".size", true);
    s.tools.push_back(tool);
  }
  const json& actions = required(root, "actions", name, "(top level)");
  if (!actions.is_array()) fail(name, "actions", "expected an array");
  for (std::size_t i = 0; i < actions.size(); ++i) {
    const std::string w = "actions[" + std::to_string(i) + "]";
    const json& a = actions[i];
    if (!a.is_object()) fail(name, w, "expected an object");
    ScriptAction act;
    act.time = number(required(a, "time", name, w), name, w + ".time", true);
    if (auto it = a.find("duration"); it != a.end()) act.duration = number(*it, name, w + ".duration", true);
    const json& tn = required(a, "tool", name, w);
    if (!tn.is_string()) fail(name, w + ".tool", "expected a tool name");
    const std::string tool_name = tn.get<std::string>();
    auto found = std::find_if(s.tools.begin(), s.tools.end(), [&](const ScriptTool& t) { return t.name == tool_name; });
    if (found == s.tools.end()) fail(name, w + ".tool", "no tool named '" + tool_name + "' in \"tools\"");
    act.tool = static_cast<int>(found - s.tools.begin());
    const ToolKind kind = found->kind;
    const json& ty = required(a, "type", name, w);
    if (!ty.is_string()) fail(name, w + ".type", "expected a string");
    const std::string type = ty.get<std::string>();
    if (type == "press") {
      act.type = ActionType::Press;
      act.at = vec3(required(a, "at", name, w), name, w + ".at");
      act.direction = unit3(required(a, "direction", name, w), name, w + ".direction");
      act.offset = number(required(a, "depth", name, w), name, w + ".depth", true) * act.direction;
    } else if (type == "pinch" || type == "retract") {
      act.type = type == "pinch" ? ActionType::Pinch : ActionType::Retract;
      act.at = vec3(required(a, "at", name, w), name, w + ".at");
      act.direction = unit3(required(a, "direction", name, w), name, w + ".direction");
      act.offset = vec3(required(a, "pull", name, w), name, w + ".pull");
    } else if (type == "move") {
      act.type = ActionType::Move;
      act.offset = vec3(required(a, "to", name, w), name, w + ".to");
    } else if (type == "release") {
      act.type = ActionType::Release;
    } else if (type == "cut") {
      act.type = ActionType::Cut;
      if (kind != ToolKind::Cut) fail(name, w + ".tool", "a cut needs a tool of type \"cut\"");
      act.at = vec3(required(a, "from", name, w), name, w + ".from");
      act.direction = unit3(required(a, "direction", name, w), name, w + ".direction");
      const json& st = required(a, "steps", name, w);
      if (!st.is_number_integer() || st.get<long>() < 1 || st.get<long>() > 1000)
        fail(name, w + ".steps", "expected an integer from 1 to 1000");
      act.steps = static_cast<int>(st.get<long>());
    } else {
      fail(name, w + ".type", "unknown action '" + type + "' (press, pinch, retract, move, release, cut)");
    }
    if ((act.type == ActionType::Press || act.type == ActionType::Pinch || act.type == ActionType::Retract) &&
        kind == ToolKind::Cut)
      fail(name, w + ".tool", "a cut tool cannot " + type);
    s.actions.push_back(act);
  }
  std::stable_sort(s.actions.begin(), s.actions.end(),
                   [](const ScriptAction& x, const ScriptAction& y) { return x.time < y.time; });
  return s;
}

ScriptPlayer::ScriptPlayer(ActionScript script) : script_(std::move(script)) {}

ToolPose ScriptPlayer::pose(int tool, double t) const {
  // Replays the tool's actions up to t: an engagement (press/pinch/retract) starts a translation
  // ramp from zero to its offset; a move ramps from the translation reached so far to its target;
  // release ends the engagement.
  ToolPose p;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  double t0 = 0.0, dur = 0.0;
  for (const auto& a : script_.actions) {
    if (a.tool != tool || a.time > t) continue;
    auto ramp = [&](double time) {
      if (dur <= 0.0 || time >= t0 + dur) return to;
      const double s = std::clamp((time - t0) / dur, 0.0, 1.0);
      return Eigen::Vector3d(from + s * (to - from));
    };
    switch (a.type) {
      case ActionType::Press:
      case ActionType::Pinch:
      case ActionType::Retract:
        p.engaged = true;
        p.at = a.at;
        p.direction = a.direction;
        from.setZero();
        to = a.offset;
        t0 = a.time;
        dur = a.duration;
        break;
      case ActionType::Move:
        from = ramp(a.time);
        to = a.offset;
        t0 = a.time;
        dur = a.duration;
        break;
      case ActionType::Release:
        p.engaged = false;
        from.setZero();
        to.setZero();
        break;
      case ActionType::Cut:
        break;
    }
  }
  if (p.engaged) {
    if (dur <= 0.0 || t >= t0 + dur)
      p.translation = to;
    else
      p.translation = from + std::clamp((t - t0) / dur, 0.0, 1.0) * (to - from);
  }
  return p;
}

std::vector<ScriptCut> ScriptPlayer::cuts_between(double t0, double t1) const {
  std::vector<ScriptCut> out;
  for (std::size_t ai = 0; ai < script_.actions.size(); ++ai) {
    const ScriptAction& a = script_.actions[ai];
    if (a.type != ActionType::Cut) continue;
    for (int i = 0; i < a.steps; ++i) {
      const double time = a.time + (a.steps > 1 ? a.duration * i / (a.steps - 1) : 0.0);
      if (time > t0 && time <= t1) out.push_back({time, a.tool, static_cast<int>(ai), a.at, a.direction});
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const ScriptCut& x, const ScriptCut& y) { return x.time < y.time; });
  return out;
}

}  // namespace bemsurg::viewer
