// Action scripts (bemsurg/io/action_script.hpp, docs/actions.md): JSON in, checked timed actions
// out. Every check throws SceneError whose message starts with the file and the key path
// ("probe.json: actions[2].direction: must be a non-zero vector").
#include "bemsurg/io/action_script.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bemsurg/error.hpp"

namespace bemsurg {

const char* to_string(ScriptToolShape shape) {
  switch (shape) {
    case ScriptToolShape::Point: return "point";
    case ScriptToolShape::Flat: return "flat";
    case ScriptToolShape::Sphere: return "sphere";
    case ScriptToolShape::Pinch: return "pinch";
    case ScriptToolShape::Plate: return "plate";
    case ScriptToolShape::Blade: return "blade";
  }
  return "?";
}

const char* to_string(ActionType type) {
  switch (type) {
    case ActionType::Move: return "move";
    case ActionType::Press: return "press";
    case ActionType::Pinch: return "pinch";
    case ActionType::Release: return "release";
    case ActionType::Retract: return "retract";
    case ActionType::Cut: return "cut";
  }
  return "?";
}

double Action::end_time() const {
  if (type == ActionType::Cut) return time + (steps - 1) * step_interval;
  return time + duration;
}

int ActionScript::tool_index(const std::string& name) const {
  for (std::size_t i = 0; i < tools.size(); ++i)
    if (tools[i].name == name) return static_cast<int>(i);
  return -1;
}

bool ActionScript::has_cuts() const {
  return std::any_of(actions.begin(), actions.end(), [](const Action& a) { return a.type == ActionType::Cut; });
}

namespace {

using nlohmann::json;

/// Throws with the file name and key path in front, as docs/actions.md promises.
class Reader {
 public:
  explicit Reader(std::string name) : name_(std::move(name)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(name_ + ": " + (key.empty() ? "" : key + ": ") + what);
  }
  static std::string child(const std::string& parent, const std::string& key) {
    return parent.empty() ? key : parent + "." + key;
  }
  static std::string item(const std::string& parent, std::size_t i) { return parent + "[" + std::to_string(i) + "]"; }

  static std::string describe(const json& v) {
    switch (v.type()) {
      case json::value_t::null: return "null";
      case json::value_t::object: return "an object";
      case json::value_t::array: return "an array";
      case json::value_t::string: return "a string";
      case json::value_t::boolean: return "a boolean";
      default: return "a number";
    }
  }
  void object(const json& v, const std::string& key) const {
    if (!v.is_object()) fail(key, "expected an object, got " + describe(v));
  }
  const json& required(const json& obj, const char* name, const std::string& parent) const {
    const auto it = obj.find(name);
    if (it == obj.end()) fail(child(parent, name), "missing (required)");
    return *it;
  }
  static const json* optional(const json& obj, const char* name) {
    const auto it = obj.find(name);
    return it == obj.end() ? nullptr : &*it;
  }
  double number(const json& v, const std::string& key) const {
    if (!v.is_number()) fail(key, "expected a number, got " + describe(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(key, "expected a finite number");
    return x;
  }
  double non_negative(const json& v, const std::string& key) const {
    const double x = number(v, key);
    if (x < 0.0) fail(key, "must not be negative, got " + json(x).dump());
    return x;
  }
  double positive(const json& v, const std::string& key) const {
    const double x = number(v, key);
    if (!(x > 0.0)) fail(key, "must be positive, got " + json(x).dump());
    return x;
  }
  long long integer(const json& v, const std::string& key) const {
    if (v.is_number_integer()) return v.get<long long>();
    if (v.is_number_float()) {
      const double x = v.get<double>();
      if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9.0e15) return static_cast<long long>(x);
      fail(key, "expected an integer, got " + v.dump());
    }
    fail(key, "expected an integer, got " + describe(v));
  }
  int integer_in(const json& v, const std::string& key, long long lo, long long hi) const {
    const long long x = integer(v, key);
    if (x < lo || x > hi)
      fail(key, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(x));
    return static_cast<int>(x);
  }
  std::string string(const json& v, const std::string& key) const {
    if (!v.is_string()) fail(key, "expected a string, got " + describe(v));
    return v.get<std::string>();
  }
  Eigen::Vector3d vec3(const json& v, const std::string& key) const {
    if (!v.is_array() || v.size() != 3)
      fail(key, "expected an array of 3 numbers, got " +
                    (v.is_array() ? "an array of " + std::to_string(v.size()) : describe(v)));
    Eigen::Vector3d out;
    for (std::size_t i = 0; i < 3; ++i) out(static_cast<Eigen::Index>(i)) = number(v[i], item(key, i));
    return out;
  }
  Eigen::Vector3d unit(const json& v, const std::string& key) const {
    const Eigen::Vector3d d = vec3(v, key);
    const double n = d.stableNorm();
    if (!(n > 0.0) || !std::isfinite(n)) fail(key, "must be a non-zero vector");
    return d / n;
  }
  void unknown_keys(const json& obj, const std::string& parent, std::initializer_list<const char*> known,
                    std::vector<std::string>& warnings) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      const std::string& k = it.key();
      if (k.empty() || k[0] == '_' || k == "comment" || k == "description" || k == "title") continue;
      bool found = false;
      for (const char* n : known) found = found || k == n;
      if (found) continue;
      std::string list;
      for (const char* n : known) list += (list.empty() ? "" : ", ") + std::string(n);
      warnings.push_back(name_ + ": " + child(parent, k) + ": unknown key, ignored (known here: " + list + ")");
    }
  }

 private:
  std::string name_;
};

ScriptToolShape parse_shape(const Reader& r, const json& v, const std::string& key) {
  const std::string s = r.string(v, key);
  for (ScriptToolShape shape : {ScriptToolShape::Point, ScriptToolShape::Flat, ScriptToolShape::Sphere,
                                ScriptToolShape::Pinch, ScriptToolShape::Plate, ScriptToolShape::Blade})
    if (s == to_string(shape)) return shape;
  r.fail(key, "unknown tool shape '" + s + "' (known: point, flat, sphere, pinch, plate, blade)");
}

ActionType parse_type(const Reader& r, const json& v, const std::string& key) {
  const std::string s = r.string(v, key);
  for (ActionType t : {ActionType::Move, ActionType::Press, ActionType::Pinch, ActionType::Release, ActionType::Retract,
                       ActionType::Cut})
    if (s == to_string(t)) return t;
  r.fail(key, "unknown action type '" + s + "' (known: move, press, pinch, release, retract, cut)");
}

ScriptTool parse_tool(const Reader& r, const json& v, const std::string& key, std::vector<std::string>& warnings) {
  r.object(v, key);
  ScriptTool t;
  t.name = r.string(r.required(v, "name", key), Reader::child(key, "name"));
  if (t.name.empty()) r.fail(Reader::child(key, "name"), "must not be empty");
  t.shape = parse_shape(r, r.required(v, "shape", key), Reader::child(key, "shape"));
  t.frictionless = t.shape == ScriptToolShape::Sphere || t.shape == ScriptToolShape::Flat;
  const bool needs_radius = t.shape == ScriptToolShape::Sphere || t.shape == ScriptToolShape::Flat;
  if (const json* x = Reader::optional(v, "radius"))
    t.radius = needs_radius ? r.positive(*x, Reader::child(key, "radius")) : r.non_negative(*x, Reader::child(key, "radius"));
  else if (needs_radius)
    r.fail(Reader::child(key, "radius"), std::string("missing (a ") + to_string(t.shape) + " needs a radius)");
  if (const json* x = Reader::optional(v, "contact")) {
    const std::string c = r.string(*x, Reader::child(key, "contact"));
    if (c == "frictionless")
      t.frictionless = true;
    else if (c == "bonded")
      t.frictionless = false;
    else
      r.fail(Reader::child(key, "contact"), "must be \"bonded\" or \"frictionless\", got '" + c + "'");
    if (t.shape == ScriptToolShape::Pinch && t.frictionless)
      r.fail(Reader::child(key, "contact"), "a pinch holds the tissue, so it is bonded");
  }
  if (const json* x = Reader::optional(v, "direction")) t.direction = r.unit(*x, Reader::child(key, "direction"));
  if (t.shape == ScriptToolShape::Plate) {
    const std::string pk = Reader::child(key, "polygon");
    const json& poly = r.required(v, "polygon", key);
    if (!poly.is_array() || poly.size() < 3) r.fail(pk, "expected an array of at least 3 points");
    for (std::size_t i = 0; i < poly.size(); ++i) t.polygon.push_back(r.vec3(poly[i], Reader::item(pk, i)));
    t.plate_tolerance = r.positive(r.required(v, "tolerance", key), Reader::child(key, "tolerance"));
    if (!Reader::optional(v, "direction")) r.fail(Reader::child(key, "direction"), "missing (a plate needs its normal)");
  }
  if (const json* x = Reader::optional(v, "device")) t.device = r.integer_in(*x, Reader::child(key, "device"), 0, 15);
  if (const json* x = Reader::optional(v, "start")) {
    t.start = r.vec3(*x, Reader::child(key, "start"));
    t.has_start = true;
  }
  r.unknown_keys(v, key, {"name", "shape", "radius", "contact", "direction", "polygon", "tolerance", "device", "start"},
                 warnings);
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

Action parse_action(const Reader& r, const json& v, const std::string& key, const ActionScript& script,
                    std::vector<std::string>& warnings) {
  r.object(v, key);
  Action a;
  a.time = r.non_negative(r.required(v, "time", key), Reader::child(key, "time"));
  const std::string tool = r.string(r.required(v, "tool", key), Reader::child(key, "tool"));
  a.tool = script.tool_index(tool);
  if (a.tool < 0) {
    std::string names;
    for (const auto& t : script.tools) names += (names.empty() ? "" : ", ") + t.name;
    r.fail(Reader::child(key, "tool"), "no tool named '" + tool + "' (tools: " + names + ")");
  }
  a.type = parse_type(r, r.required(v, "type", key), Reader::child(key, "type"));
  const ScriptTool& t = script.tools[static_cast<std::size_t>(a.tool)];
  if (!allowed(a.type, t.shape))
    r.fail(Reader::child(key, "type"), std::string("tool '") + t.name + "' is a " + to_string(t.shape) + " and cannot " +
                                           to_string(a.type) +
                                           " (press: point, flat, sphere; pinch: pinch; retract: plate; cut: blade)");
  auto k = [&](const char* n) { return Reader::child(key, n); };
  if (const json* x = Reader::optional(v, "duration")) a.duration = r.non_negative(*x, k("duration"));
  switch (a.type) {
    case ActionType::Move:
      a.to = r.vec3(r.required(v, "to", key), k("to"));
      r.unknown_keys(v, key, {"time", "tool", "type", "duration", "to"}, warnings);
      break;
    case ActionType::Press:
      a.at = r.vec3(r.required(v, "at", key), k("at"));
      a.direction = Reader::optional(v, "direction") ? r.unit(v["direction"], k("direction")) : t.direction;
      a.depth = r.non_negative(r.required(v, "depth", key), k("depth"));
      r.unknown_keys(v, key, {"time", "tool", "type", "duration", "at", "direction", "depth"}, warnings);
      break;
    case ActionType::Pinch:
      a.at = r.vec3(r.required(v, "at", key), k("at"));
      a.direction = Reader::optional(v, "direction") ? r.unit(v["direction"], k("direction")) : t.direction;
      r.unknown_keys(v, key, {"time", "tool", "type", "duration", "at", "direction"}, warnings);
      break;
    case ActionType::Release:
      r.unknown_keys(v, key, {"time", "tool", "type", "duration"}, warnings);
      break;
    case ActionType::Retract:
      a.by = r.vec3(r.required(v, "by", key), k("by"));
      if (const json* x = Reader::optional(v, "rotation")) a.rotation = r.vec3(*x, k("rotation"));
      r.unknown_keys(v, key, {"time", "tool", "type", "duration", "by", "rotation"}, warnings);
      break;
    case ActionType::Cut:
      a.from = r.vec3(r.required(v, "from", key), k("from"));
      a.direction = r.unit(r.required(v, "direction", key), k("direction"));
      a.steps = r.integer_in(r.required(v, "steps", key), k("steps"), 1, 1000);
      if (const json* x = Reader::optional(v, "step_interval")) a.step_interval = r.positive(*x, k("step_interval"));
      if (Reader::optional(v, "duration")) r.fail(k("duration"), "a cut takes steps * step_interval; give step_interval");
      r.unknown_keys(v, key, {"time", "tool", "type", "from", "direction", "steps", "step_interval"}, warnings);
      break;
  }
  return a;
}

ActionScript parse(const json& root, const std::string& directory, const std::string& name) {
  const Reader r(name);
  r.object(root, "");
  ActionScript s;
  s.path = name;
  s.directory = directory;
  const std::string format = r.string(r.required(root, "format", ""), "format");
  if (format != "bemsurg-actions") r.fail("format", "expected \"bemsurg-actions\", got '" + format + "'");
  s.version = r.integer_in(r.required(root, "version", ""), "version", 1, 1000);
  if (s.version != 1) r.fail("version", "this bemsurg reads action scripts of version 1, got " + std::to_string(s.version));
  if (const json* x = Reader::optional(root, "scene")) {
    s.scene = r.string(*x, "scene");
    if (!s.scene.empty() && std::filesystem::path(s.scene).is_relative())
      s.scene = (std::filesystem::path(directory) / s.scene).lexically_normal().string();
  }
  if (const json* x = Reader::optional(root, "rate_hz")) {
    s.rate_hz = r.number(*x, "rate_hz");
    if (!(s.rate_hz >= 100.0 && s.rate_hz <= 10000.0))
      r.fail("rate_hz", "must lie in [100, 10000] Hz, got " + json(s.rate_hz).dump());
  }
  if (const json* x = Reader::optional(root, "capacity_rows")) s.capacity_rows = r.integer_in(*x, "capacity_rows", 3, 3000);
  const json& tools = r.required(root, "tools", "");
  if (!tools.is_array() || tools.empty()) r.fail("tools", "expected a non-empty array of tools");
  for (std::size_t i = 0; i < tools.size(); ++i) {
    ScriptTool t = parse_tool(r, tools[i], Reader::item("tools", i), s.warnings);
    if (s.tool_index(t.name) >= 0) r.fail(Reader::item("tools", i) + ".name", "a tool named '" + t.name + "' is already defined");
    if (!Reader::optional(tools[i], "device")) t.device = static_cast<int>(i);
    for (std::size_t j = 0; j < s.tools.size(); ++j)
      if (s.tools[j].device == t.device)
        r.fail(Reader::item("tools", i) + ".device", "device channel " + std::to_string(t.device) + " already drives tool '" +
                                                         s.tools[j].name + "' (one tool per channel)");
    s.tools.push_back(std::move(t));
  }
  const json& actions = r.required(root, "actions", "");
  if (!actions.is_array()) r.fail("actions", "expected an array of actions, got " + Reader::describe(actions));
  std::vector<std::pair<Action, std::size_t>> parsed;
  for (std::size_t i = 0; i < actions.size(); ++i)
    parsed.emplace_back(parse_action(r, actions[i], Reader::item("actions", i), s, s.warnings), i);
  std::stable_sort(parsed.begin(), parsed.end(), [](const auto& a, const auto& b) { return a.first.time < b.first.time; });
  // One tool does one thing at a time: an action may not start before that tool's last one ended.
  std::vector<std::pair<double, std::size_t>> busy(s.tools.size(), {-1.0, 0});
  for (const auto& [a, i] : parsed) {
    auto& [end, index] = busy[static_cast<std::size_t>(a.tool)];
    if (a.time < end - 1e-12)
      r.fail(Reader::item("actions", i) + ".time",
             "tool '" + s.tools[static_cast<std::size_t>(a.tool)].name + "' is still busy with actions[" +
                 std::to_string(index) + "] until t = " + json(end).dump() + " s");
    end = a.end_time();
    index = i;
    s.actions.push_back(a);
  }
  double last = 0.0;
  for (const Action& a : s.actions) last = std::max(last, a.end_time());
  if (const json* x = Reader::optional(root, "duration")) {
    s.duration = r.positive(*x, "duration");
    if (s.duration < last) r.fail("duration", "is shorter than the last action, which ends at t = " + json(last).dump() + " s");
  } else {
    s.duration = last + 0.1;
  }
  r.unknown_keys(root, "",
                 {"format", "version", "scene", "rate_hz", "duration", "capacity_rows", "tools", "actions", "name"},
                 s.warnings);
  return s;
}

}  // namespace

ActionScript load_action_script_from_string(const std::string& json_text, const std::string& directory,
                                            const std::string& name) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw SceneError(name + ": not valid JSON: " + e.what());
  }
  return parse(root, directory, name);
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
