// Tests for action scripts (io/action_script.hpp, docs/actions.md): a full script parses into the
// documented values, and each kind of mistake is refused with the file and key path at fault.
#include <catch2/catch.hpp>
#include <limits>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/io/action_script.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {
using bemsurg_test::kEps;
const char* kScript = R"({
  "format": "bemsurg-actions", "version": 1,
  "scene": "block.json", "rate_hz": 2000, "capacity_rows": 120,
  "tools": [
    {"name": "probe", "shape": "sphere", "radius": 0.004},
    {"name": "grasper", "shape": "pinch", "radius": 0.002, "device": 1},
    {"name": "retractor", "shape": "plate", "direction": [0, 0, -1], "tolerance": 0.001,
     "polygon": [[-0.01, -0.01, 0.05], [0.01, -0.01, 0.05], [0.01, 0.01, 0.05]], "device": 2},
    {"name": "scalpel", "shape": "blade", "device": 3}
  ],
  "actions": [
    {"time": 0.5, "tool": "probe", "type": "press", "at": [0, 0, 0.06], "direction": [0, 0, -2], "depth": 0.002, "duration": 0.25},
    {"time": 0.0, "tool": "probe", "type": "move", "to": [0, 0, 0.07], "duration": 0.5},
    {"time": 0.1, "tool": "grasper", "type": "pinch", "at": [0.02, 0, 0.06]},
    {"time": 0.2, "tool": "grasper", "type": "move", "to": [0.02, 0, 0.065], "duration": 0.3},
    {"time": 0.6, "tool": "grasper", "type": "release"},
    {"time": 1.0, "tool": "retractor", "type": "retract", "by": [0.003, 0, 0], "rotation": [0, 0.01, 0], "duration": 0.5},
    {"time": 1.0, "tool": "scalpel", "type": "cut", "from": [0, 0.01, 0.05], "direction": [1, 0, 0], "steps": 3, "step_interval": 0.2}
  ]
})";

std::string error_of(const std::string& text) {
  try {
    load_action_script_from_string(text, ".", "s.json");
  } catch (const SceneError& e) { return e.what(); }
  return "(no error)";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}
}  // namespace

TEST_CASE("a full action script parses into tools and time-sorted actions", "[actions]") {
  const ActionScript s = load_action_script_from_string(kScript, "/scripts", "s.json");
  CHECK(s.version == 1);
  CHECK(s.scene == "/scripts/block.json");
  CHECK(s.rate_hz == 2000.0);
  CHECK(s.capacity_rows == 120);
  REQUIRE(s.tools.size() == 4);
  CHECK(s.tools[0].shape == ScriptToolShape::Sphere);
  CHECK(s.tools[0].frictionless);   // a sphere's default
  CHECK(s.tools[0].device == 0);    // default: its index
  CHECK(!s.tools[1].frictionless);  // a pinch is bonded
  CHECK(s.tools[2].polygon.size() == 3);
  CHECK(s.tools[2].plate_tolerance == 0.001);
  REQUIRE(s.actions.size() == 7);
  CHECK(s.actions[0].type == ActionType::Move);                 // sorted by time
  CHECK(s.actions[0].end_time() == Approx(0.5).epsilon(kEps));  // 0 + 0.5: measured 0
  const Action& press = s.actions[3];
  CHECK(press.type == ActionType::Press);
  CHECK((press.direction - Eigen::Vector3d(0, 0, -1)).norm() < 1e-15);  // normalised: measured 0; bound ~4.5 eps
  CHECK(press.depth == 0.002);
  const Action& cut = s.actions.back();
  CHECK(cut.type == ActionType::Cut);
  CHECK(cut.steps == 3);
  CHECK(cut.end_time() == Approx(1.4).epsilon(2 * kEps));  // 1 + 2 x 0.2, two roundings: measured 0
  CHECK(s.has_cuts());
  CHECK(s.duration == Approx(1.6).epsilon(2 * kEps));  // last end (retract 1.5, cut 1.4) + 0.1: measured 0
  CHECK(s.warnings.empty());
}

TEST_CASE("action script mistakes name the file and the key at fault", "[actions]") {
  CHECK(error_of("{").find("s.json: not valid JSON") == 0);
  CHECK(error_of(replace(kScript, "\"bemsurg-actions\"", "\"scene\"")).find("s.json: format: expected \"bemsurg-actions\"") == 0);
  CHECK(error_of(replace(kScript, "\"version\": 1", "\"version\": 2")).find("s.json: version:") == 0);
  CHECK(error_of(replace(kScript, "\"depth\": 0.002", "\"depth\": \"2\"")) == "s.json: actions[0].depth: expected a number, got a string");
  CHECK(error_of(replace(kScript, "\"tool\": \"grasper\", \"type\": \"pinch\"", "\"tool\": \"gripper\", \"type\": \"pinch\"")) ==
        "s.json: actions[2].tool: no tool named 'gripper' (tools: probe, grasper, retractor, scalpel)");
  CHECK(error_of(replace(kScript, "\"type\": \"pinch\"", "\"type\": \"squeeze\""))
            .find("s.json: actions[2].type: unknown action type 'squeeze'") == 0);
  CHECK(error_of(replace(kScript, "\"tool\": \"grasper\", \"type\": \"pinch\"", "\"tool\": \"probe\", \"type\": \"pinch\""))
            .find("s.json: actions[2].type: tool 'probe' is a sphere and cannot pinch") == 0);
  CHECK(error_of(replace(kScript, "\"direction\": [0, 0, -2]", "\"direction\": [0, 0, 0]")) ==
        "s.json: actions[0].direction: must be a non-zero vector");
  CHECK(error_of(replace(kScript, "\"radius\": 0.004", "\"radius\": -1")) == "s.json: tools[0].radius: must be positive, got -1.0");
  CHECK(error_of(replace(kScript, "\"shape\": \"sphere\", \"radius\": 0.004", "\"shape\": \"sphere\""))
            .find("s.json: tools[0].radius: missing") == 0);
  CHECK(error_of(replace(kScript, "\"time\": 0.5, \"tool\": \"probe\"", "\"time\": 0.4, \"tool\": \"probe\""))
            .find("s.json: actions[0].time: tool 'probe' is still busy with actions[1] until t = 0.5 s") == 0);
  CHECK(error_of(replace(kScript, "\"time\": 0.0,", "\"time\": -1,")).find("s.json: actions[1].time: must not be negative") == 0);
  CHECK(error_of(replace(kScript, "\"steps\": 3", "\"steps\": 0")).find("s.json: actions[6].steps: must lie in [1, 1000]") == 0);
  CHECK(error_of(replace(kScript, "\"device\": 1", "\"device\": 0"))
            .find("s.json: tools[1].device: device channel 0 already drives tool 'probe'") == 0);
  CHECK(error_of(replace(kScript, "\"rate_hz\": 2000", "\"rate_hz\": 20000")).find("s.json: rate_hz: must lie in [100, 10000]") == 0);
  CHECK(error_of(replace(kScript, "\"polygon\"", "\"poly\"")).find("s.json: tools[2].polygon: missing") == 0);
}

TEST_CASE("unknown keys in an action script are warnings, not errors", "[actions]") {
  const ActionScript s =
      load_action_script_from_string(replace(kScript, "\"depth\": 0.002", "\"depth\": 0.002, \"deep\": 1"), ".", "s.json");
  REQUIRE(s.warnings.size() == 1);
  CHECK(s.warnings[0].find("s.json: actions[0].deep: unknown key, ignored") == 0);
}
