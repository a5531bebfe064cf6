// Action scripts (bemsurg/io/action_script.hpp, docs/actions.md): JSON in, checked timed actions
// out. Every check throws SceneError whose message starts with the file and the key path
// ("probe.json: actions[2].direction: must be a non-zero vector").
#include "bemsurg/io/action_script.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>

#include "bemsurg/error.hpp"
#include "json_reader.hpp"

namespace bemsurg {

namespace {

using io::JsonReader;

ScriptToolShape parse_shape(const JsonReader& v) {
  const std::string s = v.string();
  for (ScriptToolShape shape : {ScriptToolShape::Point, ScriptToolShape::Flat, ScriptToolShape::Sphere, ScriptToolShape::Pinch,
                                ScriptToolShape::Plate, ScriptToolShape::Blade})
    if (s == to_string(shape)) return shape;
  v.fail("unknown tool shape '" + s + "' (known: point, flat, sphere, pinch, plate, blade)");
}

ActionType parse_type(const JsonReader& v) {
  const std::string s = v.string();
  for (ActionType t : {ActionType::Move, ActionType::Press, ActionType::Pinch, ActionType::Release, ActionType::Retract, ActionType::Cut})
    if (s == to_string(t)) return t;
  v.fail("unknown action type '" + s + "' (known: move, press, pinch, release, retract, cut)");
}

ScriptTool parse_tool(const JsonReader& v) {
  v.object();
  ScriptTool t;
  const JsonReader name = v.required("name");
  t.name = name.string();
  if (t.name.empty()) name.fail("must not be empty");
  t.shape = parse_shape(v.required("shape"));
  t.frictionless = t.shape == ScriptToolShape::Sphere || t.shape == ScriptToolShape::Flat;
  const bool needs_radius = t.shape == ScriptToolShape::Sphere || t.shape == ScriptToolShape::Flat;
  if (const std::optional<JsonReader> x = v.optional("radius"))
    t.radius = needs_radius ? x->positive() : x->non_negative();
  else if (needs_radius)
    v.fail_at(v.path_of("radius"), std::string("missing (a ") + to_string(t.shape) + " needs a radius)");
  if (const std::optional<JsonReader> x = v.optional("contact")) {
    const std::string c = x->string();
    if (c == "frictionless")
      t.frictionless = true;
    else if (c == "bonded")
      t.frictionless = false;
    else
      x->fail("must be \"bonded\" or \"frictionless\", got '" + c + "'");
    if (t.shape == ScriptToolShape::Pinch && t.frictionless) x->fail("a pinch holds the tissue, so it is bonded");
  }
  if (const std::optional<JsonReader> x = v.optional("direction")) t.direction = x->unit();
  if (t.shape == ScriptToolShape::Plate) {
    const JsonReader poly = v.required("polygon");
    if (!poly.is_array() || poly.size() < 3) poly.fail("expected an array of at least 3 points");
    for (std::size_t i = 0; i < poly.size(); ++i) t.polygon.push_back(poly[i].vec3());
    t.plate_tolerance = v.required("tolerance").positive();
    if (!v.has("direction")) v.fail_at(v.path_of("direction"), "missing (a plate needs its normal)");
  }
  if (const std::optional<JsonReader> x = v.optional("device")) t.device = x->integer_in(0, 15);
  if (const std::optional<JsonReader> x = v.optional("start")) {
    t.start = x->vec3();
    t.has_start = true;
  }
  v.warn_unknown_keys({"name", "shape", "radius", "contact", "direction", "polygon", "tolerance", "device", "start"});
  return t;
}

/// Which tool shapes can do which action (docs/actions.md, "What each tool can do").
bool allowed(ActionType a, ScriptToolShape s) {
  switch (a) {
    case ActionType::Move:
    case ActionType::Release: return true;
    case ActionType::Press: return s == ScriptToolShape::Point || s == ScriptToolShape::Flat || s == ScriptToolShape::Sphere;
    case ActionType::Pinch: return s == ScriptToolShape::Pinch;
    case ActionType::Retract: return s == ScriptToolShape::Plate;
    case ActionType::Cut: return s == ScriptToolShape::Blade;
  }
  return false;
}

Action parse_action(const JsonReader& v, const ActionScript& script) {
  v.object();
  Action a;
  a.time = v.required("time").non_negative();
  const JsonReader tool_key = v.required("tool");
  const std::string tool = tool_key.string();
  a.tool = script.tool_index(tool);
  if (a.tool < 0) {
    std::string names;
    for (const auto& t : script.tools) names += (names.empty() ? "" : ", ") + t.name;
    tool_key.fail("no tool named '" + tool + "' (tools: " + names + ")");
  }
  const JsonReader type_key = v.required("type");
  a.type = parse_type(type_key);
  const ScriptTool& t = script.tools[static_cast<std::size_t>(a.tool)];
  if (!allowed(a.type, t.shape))
    type_key.fail(std::string("tool '") + t.name + "' is a " + to_string(t.shape) + " and cannot " + to_string(a.type) +
                  " (press: point, flat, sphere; pinch: pinch; retract: plate; cut: blade)");
  if (const std::optional<JsonReader> x = v.optional("duration")) a.duration = x->non_negative();
  const auto direction_or_tool = [&] {
    const std::optional<JsonReader> d = v.optional("direction");
    return d ? d->unit() : t.direction;
  };
  switch (a.type) {
    case ActionType::Move:
      a.to = v.required("to").vec3();
      v.warn_unknown_keys({"time", "tool", "type", "duration", "to"});
      break;
    case ActionType::Press:
      a.at = v.required("at").vec3();
      a.direction = direction_or_tool();
      a.depth = v.required("depth").non_negative();
      v.warn_unknown_keys({"time", "tool", "type", "duration", "at", "direction", "depth"});
      break;
    case ActionType::Pinch:
      a.at = v.required("at").vec3();
      a.direction = direction_or_tool();
      v.warn_unknown_keys({"time", "tool", "type", "duration", "at", "direction"});
      break;
    case ActionType::Release: v.warn_unknown_keys({"time", "tool", "type", "duration"}); break;
    case ActionType::Retract:
      a.by = v.required("by").vec3();
      if (const std::optional<JsonReader> x = v.optional("rotation")) a.rotation = x->vec3();
      v.warn_unknown_keys({"time", "tool", "type", "duration", "by", "rotation"});
      break;
    case ActionType::Cut:
      a.from = v.required("from").vec3();
      a.direction = v.required("direction").unit();
      a.steps = v.required("steps").integer_in(1, 1000);
      if (const std::optional<JsonReader> x = v.optional("step_interval")) a.step_interval = x->positive();
      if (const std::optional<JsonReader> x = v.optional("duration")) x->fail("a cut takes steps * step_interval; give step_interval");
      v.warn_unknown_keys({"time", "tool", "type", "from", "direction", "steps", "step_interval"});
      break;
  }
  return a;
}

ActionScript parse(const io::JsonDocument& document, const std::string& directory, const std::string& name) {
  ActionScript s;
  s.path = name;
  s.directory = directory;
  const io::JsonSource source{name, &s.warnings};  // messages start with the file, as docs/actions.md promises
  const JsonReader root(document.root(), source);
  root.object();
  const JsonReader format = root.required("format");
  if (format.string() != "bemsurg-actions") format.fail("expected \"bemsurg-actions\", got '" + format.string() + "'");
  const JsonReader version = root.required("version");
  s.version = version.integer_in(1, 1000);
  if (s.version != 1) version.fail("this bemsurg reads action scripts of version 1, got " + std::to_string(s.version));
  if (const std::optional<JsonReader> x = root.optional("scene")) {
    s.scene = x->string();
    if (!s.scene.empty() && std::filesystem::path(s.scene).is_relative())
      s.scene = (std::filesystem::path(directory) / s.scene).lexically_normal().string();
  }
  if (const std::optional<JsonReader> x = root.optional("rate_hz")) {
    s.rate_hz = x->number();
    if (!(s.rate_hz >= 100.0 && s.rate_hz <= 10000.0)) x->fail("must lie in [100, 10000] Hz, got " + io::json_number_text(s.rate_hz));
  }
  if (const std::optional<JsonReader> x = root.optional("capacity_rows")) s.capacity_rows = x->integer_in(3, 3000);
  const JsonReader tools = root.required("tools");
  if (!tools.is_array() || tools.empty()) tools.fail("expected a non-empty array of tools");
  for (std::size_t i = 0; i < tools.size(); ++i) {
    ScriptTool t = parse_tool(tools[i]);
    if (s.tool_index(t.name) >= 0) tools.fail_at(tools[i].path_of("name"), "a tool named '" + t.name + "' is already defined");
    if (!tools[i].has("device")) t.device = static_cast<int>(i);
    for (std::size_t j = 0; j < s.tools.size(); ++j)
      if (s.tools[j].device == t.device)
        tools.fail_at(tools[i].path_of("device"), "device channel " + std::to_string(t.device) + " already drives tool '" +
                                                      s.tools[j].name + "' (one tool per channel)");
    s.tools.push_back(std::move(t));
  }
  const JsonReader actions = root.required("actions");
  if (!actions.is_array()) actions.fail("expected an array of actions, got " + actions.type_name());
  std::vector<std::pair<Action, std::size_t>> parsed;
  for (std::size_t i = 0; i < actions.size(); ++i) parsed.emplace_back(parse_action(actions[i], s), i);
  std::stable_sort(parsed.begin(), parsed.end(), [](const auto& a, const auto& b) { return a.first.time < b.first.time; });
  // One tool does one thing at a time: an action may not start before that tool's last one ended.
  std::vector<std::pair<double, std::size_t>> busy(s.tools.size(), {-1.0, 0});
  for (const auto& [a, i] : parsed) {
    auto& [end, index] = busy[static_cast<std::size_t>(a.tool)];
    if (a.time < end - 1e-12)
      actions.fail_at(actions[i].path_of("time"), "tool '" + s.tools[static_cast<std::size_t>(a.tool)].name +
                                                      "' is still busy with actions[" + std::to_string(index) +
                                                      "] until t = " + io::json_number_text(end) + " s");
    end = a.end_time();
    index = i;
    s.actions.push_back(a);
  }
  double last = 0.0;
  for (const Action& a : s.actions) last = std::max(last, a.end_time());
  if (const std::optional<JsonReader> x = root.optional("duration")) {
    s.duration = x->positive();
    if (s.duration < last) x->fail("is shorter than the last action, which ends at t = " + io::json_number_text(last) + " s");
  } else {
    s.duration = last + 0.1;
  }
  root.warn_unknown_keys({"format", "version", "scene", "rate_hz", "duration", "capacity_rows", "tools", "actions", "name"});
  return s;
}

}  // namespace

ActionScript load_action_script_from_string(const std::string& json_text, const std::string& directory, const std::string& name) {
  return parse(io::JsonDocument(json_text, name), directory, name);
}

ActionScript load_action_script(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the action script");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string dir = std::filesystem::path(path).parent_path().string();
  ActionScript s = load_action_script_from_string(ss.str(), dir.empty() ? "." : dir, path);
  s.path = path;
  return s;
}

}  // namespace bemsurg
