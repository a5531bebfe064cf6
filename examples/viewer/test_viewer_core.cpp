// Tests of the viewer's parts that need no display: the action-script reader and player, the
// background worker's exact rescaling for Young's modulus and gravity (docs/viewer.md), and the
// haptic tick driving the contact solver through a device.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "action_script.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "model_worker.hpp"
#include "tool_stepper.hpp"

using namespace bemsurg;
using namespace bemsurg::viewer;

namespace {

// A small held block (4 x 4 x 2 divisions: 128 elements) so a precomputation takes milliseconds.
const char* kSmallScene = R"({
  "mesh": {"generator": "box", "min": [-0.04, -0.04, 0.0], "max": [0.04, 0.04, 0.04], "divisions": [4, 4, 2]},
  "material": {"young_modulus": 3000.0, "poisson_ratio": 0.45, "density": 1000.0},
  "gravity": [0.0, 0.0, -9.81],
  "boundary_conditions": {"rules": [
    {"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]}
})";

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = "test_viewer_core_" + name;
  std::ofstream(path) << text;
  return path;
}

double max_relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("a script press ramps the translation linearly and release ends the engagement", "[viewer]") {
  const ActionScript s = parse_action_script(R"({
    "tools": [{"name": "p", "type": "sphere", "radius": 0.01}],
    "actions": [
      {"time": 1.0, "tool": "p", "type": "press", "at": [0, 0, 1], "direction": [0, 0, -2], "depth": 0.004, "duration": 2.0},
      {"time": 4.0, "tool": "p", "type": "move", "to": [0.002, 0, -0.004], "duration": 1.0},
      {"time": 6.0, "tool": "p", "type": "release"}]})",
                                             "inline");
  const ScriptPlayer player(s);
  CHECK_FALSE(player.pose(0, 0.5).engaged);
  const ToolPose mid = player.pose(0, 2.0);  // halfway through the press: 2 mm along -z
  REQUIRE(mid.engaged);
  CHECK((mid.translation - Eigen::Vector3d(0, 0, -0.002)).norm() < 1e-15);
  CHECK((mid.direction - Eigen::Vector3d(0, 0, -1)).norm() < 1e-15);
  const ToolPose moving = player.pose(0, 4.5);  // halfway from (0,0,-4 mm) to (2 mm,0,-4 mm)
  CHECK((moving.translation - Eigen::Vector3d(0.001, 0, -0.004)).norm() < 1e-15);
  CHECK_FALSE(player.pose(0, 6.5).engaged);
}

TEST_CASE("script errors name the file and the key at fault", "[viewer]") {
  auto message = [](const std::string& text) {
    try {
      parse_action_script(text, "s.json");
    } catch (const InvalidArgumentError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message("{") .find("s.json: not valid JSON") == 0);
  CHECK(message(R"({"tools": [{"name": "a", "type": "spoon"}], "actions": []})").find("tools[0].type: unknown tool type 'spoon'") != std::string::npos);
  CHECK(message(R"({"tools": [{"name": "a", "type": "sphere"}], "actions": [{"time": 0, "tool": "a", "type": "press", "at": [0, 0], "direction": [0, 0, 1], "depth": 1}]})")
            .find("s.json: actions[0].at: expected an array of three numbers") == 0);
  CHECK(message(R"({"tools": [{"name": "a", "type": "sphere"}], "actions": [{"time": 0, "tool": "a", "type": "press", "at": [0, 0, 0], "direction": [0, 0, 0], "depth": 1}]})")
            .find("actions[0].direction: expected a nonzero direction") != std::string::npos);
  CHECK(message(R"({"tools": [{"name": "a", "type": "sphere"}], "actions": [{"time": 0, "tool": "a", "type": "cut", "from": [0, 0, 0], "direction": [1, 0, 0], "steps": 2}]})")
            .find("a cut needs a tool of type \"cut\"") != std::string::npos);
}

TEST_CASE("rescaling the table for E and gravity equals a recomputation with those values", "[viewer]") {
  const std::string path = write_temp("scene.json", kSmallScene);
  ModelWorker worker;
  worker.load(path);
  worker.wait_idle();
  REQUIRE(worker.status().error.empty());
  REQUIRE(worker.state()->table);
  REQUIRE(worker.status().rescale_exact);

  worker.set_young_modulus(7500.0);
  worker.wait_idle();
  const auto rescaled = worker.state();
  REQUIRE(rescaled->table);
  const Scene scene = load_scene(path);
  Material m = scene.problem.material;
  m.young_modulus = 7500.0;
  GreensTableOptions options;
  options.gravity = scene.problem.gravity;
  const GreensTable direct = GreensTable::compute(scene.problem.mesh, m, scene.problem.boundary_conditions, options);
  // Linear elasticity: exact up to round-off (measured below 1e-15 relative; bound 1e-12).
  CHECK(max_relative(rescaled->table->columns(), direct.columns()) < 1e-12);
  CHECK(max_relative(rescaled->table->base_displacement(), direct.base_displacement()) < 1e-12);
  CHECK(max_relative(rescaled->table->base_traction(), direct.base_traction()) < 1e-12);

  worker.set_gravity(false);
  worker.wait_idle();
  const auto weightless = worker.state();
  CHECK(weightless->table->base_displacement().cwiseAbs().maxCoeff() == 0.0);
  CHECK(weightless->table->base_traction().cwiseAbs().maxCoeff() == 0.0);
  CHECK(max_relative(weightless->table->columns(), direct.columns()) < 1e-12);
  std::remove(path.c_str());
}

TEST_CASE("a scene that fails to load is reported with its file name and publishes no model", "[viewer]") {
  const std::string path = write_temp("bad.json", R"({"mesh": {"generator": "box"}})");
  ModelWorker worker;
  worker.load(path);
  worker.wait_idle();
  const WorkerStatus st = worker.status();
  CHECK(st.phase == WorkerPhase::Failed);
  CHECK(st.error.find(path) == 0);
  CHECK_FALSE(worker.state());
  std::remove(path.c_str());
}

TEST_CASE("the haptic tick presses a sphere through a device as the contact solver does directly", "[viewer]") {
  const std::string path = write_temp("scene2.json", kSmallScene);
  ModelWorker worker;
  worker.load(path);
  worker.wait_idle();
  const auto ph = worker.state();
  REQUIRE(ph->table);

  haptics::NullDevice device;
  haptics::HapticDevice* devices[kMaxTools] = {&device, nullptr};
  StepperSettings settings;
  settings.slots[0].kind = ToolKind::Sphere;
  settings.slots[0].radius = 0.03;
  settings.force_limit = 100.0;
  ToolStepper stepper;
  ContactSnapshot snap;
  haptics::DeviceState d;
  d.position = Eigen::Vector3d(0.0, 0.0, 0.1);
  d.direction = Eigen::Vector3d(0, 0, -1);
  d.button = true;
  device.set_state(d);
  stepper.tick(ph, devices, settings, snap);  // engages
  d.position.z() -= 0.008;                   // 8 mm in
  device.set_state(d);
  stepper.tick(ph, devices, settings, snap);
  const Eigen::Vector3d f = snap.slots[0].force;

  // The same press straight on the solver: the sphere resting on the surface point under the
  // axis, pushed 8 mm along -z.
  ToolContactSolver solver(*ph->mesh, *ph->table, 600);
  const int tool = solver.add_tool(ToolSpec::sphere(0.03));
  RayHit hit;
  REQUIRE(solver.base_surface().intersect_ray(Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(0, 0, -1), hit, 2.0, true));
  solver.place(tool, hit.point - 0.03 * Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, -1));
  solver.set_translation(tool, Eigen::Vector3d(0, 0, -0.008));
  solver.update();
  const Eigen::Vector3d expected = solver.force(tool);
  REQUIRE(expected.z() > 0.0);  // the tissue pushes the tool back up
  CHECK((f - expected).norm() <= 1e-12 * expected.norm());
  CHECK((device.last_force() - expected).norm() <= 1e-12 * expected.norm());  // under the 100 N limit

  // The limiter caps what the device receives, not what is displayed.
  settings.force_limit = 0.5 * expected.norm();
  stepper.tick(ph, devices, settings, snap);
  CHECK(std::abs(device.last_force().norm() - 0.5 * expected.norm()) <= 1e-12 * expected.norm());
  CHECK((snap.slots[0].force - expected).norm() <= 1e-12 * expected.norm());
  std::remove(path.c_str());
}
