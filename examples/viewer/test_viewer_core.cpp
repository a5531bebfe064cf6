// Tests of the viewer's parts that need no display: the action-script reader and player, one cut
// through the viewer's, the command line's and a session's door, the
// background worker's exact rescaling for Young's modulus and gravity (docs/viewer.md), the
// parameters panel's start from the loaded scene, and the
// haptic tick driving the contact solver through a device; a hierarchical scene precomputed and cut.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/haptics/surface_cut_hook.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/io/scene_table.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "model_worker.hpp"
#include "script_player.hpp"
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

constexpr double kEps = std::numeric_limits<double>::epsilon();

double max_relative(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("a script press becomes device keyframes from the first contact, pushed depth along the axis", "[viewer]") {
  // A flat-topped block: first contact of a press straight down is on the top face, z = 0.04.
  const TriangleMesh mesh = box_mesh(Vec3(-0.04, -0.04, 0.0), Vec3(0.04, 0.04, 0.04), 4, 4, 2);
  const TriangleBvh base(mesh);
  const ActionScript script = load_action_script_from_string(R"({
    "format": "bemsurg-actions", "version": 1,
    "tools": [{"name": "p", "shape": "sphere", "radius": 0.01}, {"name": "b", "shape": "blade"}],
    "actions": [
      {"time": 1.0, "tool": "p", "type": "press", "at": [0.005, 0.003, 1], "direction": [0, 0, -2], "depth": 0.004, "duration": 2.0},
      {"time": 4.0, "tool": "p", "type": "move", "to": [0.007, 0.003, 0.046], "duration": 1.0},
      {"time": 6.0, "tool": "p", "type": "release"},
      {"time": 2.0, "tool": "b", "type": "cut", "from": [0, 0, 0.04], "direction": [1, 0, 0], "steps": 3, "step_interval": 0.5}]})",
                                                             ".", "inline");
  const ScriptPlayer player(script);
  REQUIRE(player.tool_of_slot(0) == 0);
  CHECK(player.tool_of_slot(1) == -1);  // a blade takes no device slot
  const haptics::ScriptedDevice device(player.keyframes(0, base));
  CHECK_FALSE(device.state_at(0.5).button(0));
  // Halfway through the press: the sphere's centre one radius above the contact point (0.05),
  // pushed 2 mm down.
  // The first contact comes from a ray cast from 1e3 m away (script_player.cpp): its rounding is
  // about eps x 1e3 m; bound 4 x that, 8.9e-13 (measured 1.5e-13, and 7.5e-14 after the move).
  const double ray = 4 * 1e3 * kEps;
  const haptics::DeviceState mid = device.state_at(2.0);
  REQUIRE(mid.button(0));
  CHECK((mid.position - Eigen::Vector3d(0.005, 0.003, 0.048)).norm() < ray);
  CHECK((mid.direction - Eigen::Vector3d(0, 0, -1)).norm() < 1e-15);  // (0, 0, -2) normalised: measured 0
  // Halfway through the move from (0.005, 0.003, 0.046) to (0.007, 0.003, 0.046).
  CHECK((device.state_at(4.5).position - Eigen::Vector3d(0.006, 0.003, 0.046)).norm() < ray);
  CHECK_FALSE(device.state_at(6.5).button(0));
  const auto cuts = player.cuts_between(1.9, 2.6);
  REQUIRE(cuts.size() == 2);                             // increments at 2.0 and 2.5 (the third is at 3.0)
  CHECK(cuts[0].time == Approx(2.0).epsilon(4 * kEps));  // measured 0
  CHECK(cuts[1].time == Approx(2.5).epsilon(4 * kEps));  // measured 0
}

TEST_CASE("a press whose approach line misses the body is refused naming the action", "[viewer]") {
  const TriangleMesh mesh = box_mesh(Vec3(-0.04, -0.04, 0.0), Vec3(0.04, 0.04, 0.04), 2, 2, 1);
  const TriangleBvh base(mesh);
  const ScriptPlayer player(load_action_script_from_string(R"({
    "format": "bemsurg-actions", "version": 1,
    "tools": [{"name": "p", "shape": "point"}],
    "actions": [{"time": 0, "tool": "p", "type": "press", "at": [1, 1, 1], "direction": [0, 0, -1], "depth": 0.001}]})",
                                                           ".", "s.json"));
  try {
    player.keyframes(0, base);
    FAIL("no error");
  } catch (const SceneError& e) { CHECK(std::string(e.what()).find("s.json: actions[0] (press of 'p')") == 0); }
}

TEST_CASE("the viewer's table holds the scene's operating region only, as press and session do", "[viewer]") {
  std::string text = kSmallScene;
  text.pop_back();  // the closing brace
  text += R"(, "operating_region": {"box": {"min": [-0.041, -0.041, 0.039], "max": [0.041, 0.041, 0.041]}}})";
  const std::string path = write_temp("region.json", text);
  ModelWorker worker;
  worker.load(path);
  worker.wait_idle();
  REQUIRE(worker.status().error.empty());
  REQUIRE(worker.state()->table);
  const Scene scene = load_scene(path);
  REQUIRE(scene.operating_elements.size() == 32u);  // the 4 x 4 top, two triangles per quad
  CHECK(worker.state()->table->region() == scene.operating_elements);
  std::remove(path.c_str());
}

TEST_CASE("the parameters panel starts from the loaded scene's material and gravity, then follows the user", "[viewer]") {
  // A 2 x 2 x 1 block (32 elements): three precomputations in milliseconds.
  const auto scene_text = [](const char* material, const char* gravity) {
    return std::string(R"({"mesh": {"generator": "box", "min": [0, 0, 0], "max": [0.04, 0.04, 0.02], "divisions": [2, 2, 1]},
      "material": )") +
           material + R"(, "gravity": )" + gravity + R"(,
      "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]}})";
  };
  const std::string soft =
      write_temp("soft.json", scene_text(R"({"young_modulus": 5000.0, "poisson_ratio": 0.40, "density": 1000.0})", "[0, 0, -9.81]"));
  const std::string stiff =
      write_temp("stiff.json", scene_text(R"({"young_modulus": 250000.0, "poisson_ratio": 0.495, "density": 1000.0})", "[0, 0, 0]"));
  ModelWorker worker;
  ParameterControls controls;  // what the App holds; gui() calls follow every frame
  worker.load(soft);
  worker.wait_idle();
  REQUIRE(worker.status().error.empty());
  CHECK(controls.follow(worker));
  CHECK(controls.young_kpa == 5.0f);  // not the old defaults 3.00 and 0.45
  CHECK(controls.poisson == 0.40f);
  CHECK(controls.gravity);
  CHECK_FALSE(controls.follow(worker));  // nothing new loaded: the controls are left alone

  // The user moves the sliders: the values hold (no load since) and reach the model.
  controls.young_kpa = 8.0f;
  worker.set_young_modulus(1000.0 * controls.young_kpa);
  controls.poisson = 0.30f;
  worker.set_poisson_ratio(controls.poisson);
  worker.wait_idle();
  CHECK_FALSE(controls.follow(worker));
  CHECK(controls.young_kpa == 8.0f);
  REQUIRE(worker.state()->table);
  CHECK(worker.state()->material.young_modulus == 8000.0);
  CHECK(worker.state()->material.poisson_ratio == double(0.30f));

  // Re-loading starts again from the new scene, whose values lie outside the sliders' default ranges.
  worker.load(stiff);
  worker.wait_idle();
  REQUIRE(worker.status().error.empty());
  CHECK(controls.follow(worker));
  CHECK(controls.young_kpa == 250.0f);
  CHECK(controls.poisson == 0.495f);
  CHECK_FALSE(controls.gravity);
  CHECK_FALSE(controls.scene_gravity);
  CHECK(controls.young_max() == 250.0f);
  CHECK(controls.poisson_max() == 0.495f);
  std::remove(soft.c_str());
  std::remove(stiff.c_str());
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
  // Linear elasticity: exact up to round-off. The recomputation is a fresh solve of 384 equations;
  // this box's shape and nu are those of tests/test_cut_algebra.cpp's body, whose column-equilibrated
  // system has condition number 21.3 (LU does not depend on the column scaling that E changes):
  // c n eps with c = 25, n = 384, 2.1e-12. Measured 1.0e-15, 5.9e-15, 7.8e-15.
  const double tol = 25.0 * 384.0 * kEps;
  CHECK(max_relative(rescaled->table->columns(), direct.columns()) < tol);
  CHECK(max_relative(rescaled->table->base_displacement(), direct.base_displacement()) < tol);
  CHECK(max_relative(rescaled->table->base_traction(), direct.base_traction()) < tol);

  worker.set_gravity(false);
  worker.wait_idle();
  const auto weightless = worker.state();
  CHECK(weightless->table->base_displacement().cwiseAbs().maxCoeff() == 0.0);
  CHECK(weightless->table->base_traction().cwiseAbs().maxCoeff() == 0.0);
  CHECK(max_relative(weightless->table->columns(), direct.columns()) < tol);  // measured 1.0e-15
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

/// The small scene loaded and precomputed by a worker, a sphere tool (radius 30 mm, force limit 100 N)
/// on slot 0 driven by a null device 0.1 m above the top face with its button down.
struct SphereRig {
  std::string path;
  ModelWorker worker;
  std::shared_ptr<const PhysicsState> ph;
  haptics::NullDevice device;
  haptics::HapticDevice* devices[kMaxTools] = {&device, nullptr};
  StepperOptions settings;
  ToolStepper stepper;
  ContactSnapshot snap;
  haptics::DeviceState d;
  explicit SphereRig(const std::string& name) : path(write_temp(name, kSmallScene)) {
    worker.load(path);
    worker.wait_idle();
    ph = worker.state();
    settings.slots[0].kind = ToolKind::Sphere;
    settings.slots[0].radius = 0.03;
    settings.force_limit = 100.0;
    d.position = Eigen::Vector3d(0.0, 0.0, 0.1);
    d.direction = Eigen::Vector3d(0, 0, -1);
    d.buttons = 1;
    device.set_state(d);
  }
  ~SphereRig() { std::remove(path.c_str()); }
};

TEST_CASE("the haptic tick presses a sphere through a device as the contact solver does directly", "[viewer]") {
  SphereRig rig("scene2.json");
  const auto& ph = rig.ph;
  REQUIRE(ph->table);
  rig.stepper.tick(ph, rig.devices, rig.settings, 0.0, 1e-3, rig.snap);  // engages
  const Eigen::Vector3d sent_first = rig.device.last_force();
  rig.d.position.z() -= 0.008;  // 8 mm in
  rig.device.set_state(rig.d);
  rig.stepper.tick(ph, rig.devices, rig.settings, 1e-3, 1e-3, rig.snap);
  const Eigen::Vector3d f = rig.snap.slots[0].force;

  // The same press straight on the solver: the sphere resting on the surface point under the
  // axis, pushed 8 mm along -z.
  ToolContactSolver solver(ph->mesh, ph->table, 600);
  const int tool = solver.add_tool(ToolSpec::sphere(0.03));
  RayHit hit;
  REQUIRE(solver.base_surface().intersect_ray(Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(0, 0, -1), hit, 2.0, true));
  solver.place(tool, hit.point - 0.03 * Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 0, -1));
  solver.set_translation(tool, Eigen::Vector3d(0, 0, -0.008));
  solver.update();
  const Eigen::Vector3d expected = solver.force(tool);
  REQUIRE(expected.z() > 0.0);  // the tissue pushes the tool back up
  // The same press reached from other poses: the 8 mm depth is a difference of positions up to
  // 0.1 m, so it carries 0.1 / 0.008 x 4 eps of rounding, times cond(G_CC) <= 30: 3.3e-13
  // (measured 4.5e-14).
  const double pose = 30.0 * (0.1 / 0.008) * 4 * kEps;
  CHECK((f - expected).norm() <= pose * expected.norm());
  // The rig.device gets the force through the rate limiter (300 N/s default): one tick of 1 ms after
  // the engagement tick allows at most 0.3 N (measured exactly 0.3 N; slack 8 eps for forces <= 1 N).
  CHECK((rig.device.last_force() - sent_first).norm() <= 0.3 + 8 * kEps);
  CHECK(rig.device.last_force().norm() < expected.norm());

  // The limiter caps what the rig.device receives, not what is displayed.
  rig.settings.force_limit = 0.5 * expected.norm();
  rig.settings.force_rate = 1e6;
  rig.stepper.tick(ph, rig.devices, rig.settings, 2e-3, 1e-3, rig.snap);
  CHECK(std::abs(rig.device.last_force().norm() - 0.5 * expected.norm()) <= 4 * kEps * expected.norm());  // a clip: measured 0
  CHECK((rig.snap.slots[0].force - expected).norm() <= pose * expected.norm());                           // measured 4.5e-14
}

TEST_CASE("a cut keeps the held force on the uncut model until its tables are ready, then blends the new one in", "[viewer]") {
  // Issue 26: the cut's provisional state (new surface, no table) used to reset the solver, so the
  // force fell to zero for as long as the tables took (docs/haptics.md, "Model swaps").
  SphereRig rig("scene3.json");
  const auto& ph = rig.ph;
  REQUIRE(ph->table);
  rig.settings.force_rate = 1e6;                                         // the blend alone shapes the force here
  rig.stepper.tick(ph, rig.devices, rig.settings, 0.0, 1e-3, rig.snap);  // engages
  rig.d.position.z() -= 0.008;
  rig.device.set_state(rig.d);
  rig.stepper.tick(ph, rig.devices, rig.settings, 1e-3, 1e-3, rig.snap);
  const Eigen::Vector3d held = rig.device.last_force();
  REQUIRE(held.norm() > 0.0);
  // The cut's provisional state: the same model name, one cut more, no table.
  auto provisional = std::make_shared<PhysicsState>(*ph);
  provisional->table.reset();
  provisional->cuts = ph->cuts + 1;
  provisional->version = ph->version + 1;
  for (int k = 2; k < 50; ++k) {
    rig.stepper.tick(provisional, rig.devices, rig.settings, k * 1e-3, 1e-3, rig.snap);
    REQUIRE(rig.device.last_force() == held);  // the uncut model, unchanged: exactly the same force
  }
  CHECK(rig.snap.physics_version == ph->version);
  // The cut's tables arrive (here a 2 % softer table on the same surface): blended over 30 ms.
  auto cut = std::make_shared<PhysicsState>(*provisional);
  const GreensTable& t = *ph->table;
  cut->table = std::make_shared<const GreensTable>(t.key(), t.region(), t.base_displacement(), t.base_traction(), t.base_kinds(),
                                                   Eigen::MatrixXd(1.02 * t.columns()));
  cut->version = ph->version + 2;
  rig.stepper.tick(cut, rig.devices, rig.settings, 0.050, 1e-3, rig.snap);
  const Eigen::Vector3d after = rig.snap.slots[0].force;  // the new model's
  CHECK((after - held).norm() > 0.005 * held.norm());
  CHECK((rig.device.last_force() - held).norm() <= 1e-12 * held.norm());  // weight 0: still the old force
  rig.stepper.tick(cut, rig.devices, rig.settings, 0.065, 1e-3, rig.snap);
  CHECK(rig.snap.blend_weight == Approx(0.5));
  CHECK((rig.device.last_force() - haptics::ModelCrossfade::mix(held, after, 0.5)).norm() <= 1e-9 * held.norm());
  rig.stepper.tick(cut, rig.devices, rig.settings, 0.080, 1e-3, rig.snap);
  CHECK(rig.snap.blend_weight == 1.0);
  CHECK((rig.device.last_force() - after).norm() <= 1e-12 * after.norm());
}

TEST_CASE("one cut script through the command line's, a session's and the viewer's door gives identical tables", "[viewer]") {
  // The three doors to a cut (docs/design.md §7): `bemsurg cut` (src/cli/cut_command.cpp: the scene's
  // table, CutSystemUpdate::cut), a session's hook (haptics/surface_cut_hook.hpp) and the viewer's worker
  // (request_cut_step), the last two also in two phases (a first response, then the complete table).
  // One scene with an operating region, one two-step cut; every complete table bit for bit.
  const std::string path = write_temp("doors.json", R"({
    "mesh": {"generator": "box", "min": [-0.04, -0.04, 0.0], "max": [0.04, 0.04, 0.04], "divisions": [6, 6, 2]},
    "material": {"young_modulus": 3000.0, "poisson_ratio": 0.45, "density": 1000.0},
    "gravity": [0.0, 0.0, -9.81],
    "boundary_conditions": {"rules": [
      {"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]},
    "operating_region": {"box": {"min": [-0.041, -0.041, 0.02], "max": [0.041, 0.041, 0.041]}}
  })");
  const Scene scene = load_scene(path);
  const Eigen::Vector3d from(-0.015, 0.0, 0.04), direction = Eigen::Vector3d::UnitX();
  const int steps = 2;

  // The command line's door.
  CutSystemUpdate cli(std::make_shared<const GreensTable>(compute_scene_table(scene)));
  cli.begin_cut();
  for (int i = 0; i < steps; ++i) {
    REQUIRE(cli.cut(from, direction).accepted);
    // Past the refactor rank each door refactorises (the session inline, the viewer's worker waits): so
    // that the next step starts from the same snapshot, wait here too.
    cli.wait_for_refactor();
  }
  const std::shared_ptr<const GreensTable> by_cli = cli.table();

  // A session's door: the hook, called as a session calls it for one cut action.
  haptics::CutHook hook = haptics::surface_cut_hook();
  std::shared_ptr<const GreensTable> by_session = std::make_shared<const GreensTable>(compute_scene_table(scene));
  std::shared_ptr<const TriangleMesh> mesh = by_session->mesh();
  for (int i = 0; i < steps; ++i) {
    const haptics::CutResult r = hook(haptics::CutRequest{mesh, by_session, from, direction, i, 0});
    mesh = r.mesh;
    by_session = r.table;
  }

  // The same door in two phases (docs/cutting.md, "First response"): a tool 2 cm from the cut's start.
  const Eigen::Vector3d tool(0.0, 0.02, 0.04);
  haptics::CutHook hook_two = haptics::surface_cut_hook();
  std::shared_ptr<const GreensTable> by_session_two = std::make_shared<const GreensTable>(compute_scene_table(scene));
  mesh = by_session_two->mesh();
  for (int i = 0; i < steps; ++i) {
    const haptics::CutResult r = hook_two(haptics::CutRequest{mesh, by_session_two, from, direction, i, 0, {tool}, 0.015});
    REQUIRE(r.complete);
    mesh = r.mesh;
    by_session_two = r.complete();
    CHECK(!r.table->region().empty());
    CHECK(r.table->region().size() < by_session_two->region().size());  // the first response covers the reach only
  }

  // The viewer's door, in one phase and in two (a tool's place given, as the viewer gives it every frame).
  std::shared_ptr<const GreensTable> by_viewer, by_viewer_two;
  for (int phases = 1; phases <= 2; ++phases) {
    ModelWorker worker;
    worker.load(path);
    worker.wait_idle();
    REQUIRE(worker.status().error.empty());
    if (phases == 2) {
      worker.set_cut_reach({tool}, 0.015);
      // As when the scalpel is picked: the first steps' storage is touched before any step (three
      // buffers of the table's size, held), and the steps stay exact (their tables are compared below).
      worker.prepare_cuts();
      worker.wait_idle();
      CHECK(worker.status().cut_buffers_held == 3u);
      CHECK(worker.status().cut_buffers_allocated == 0u);  // no step has needed fresh storage
      CHECK(worker.status().cut_buffers_reused == 0u);
      worker.prepare_cuts();  // again: nothing more to do
      worker.wait_idle();
      CHECK(worker.status().cut_buffers_held == 3u);
    }
    for (int i = 0; i < steps; ++i) worker.request_cut_step(i == 0, from, direction, 0.0);
    worker.wait_idle();
    REQUIRE(worker.status().cut_steps_accepted == steps);
    CHECK(worker.status().cut_first_responses == (phases == 2 ? steps : 0));
    CHECK(!worker.status().first_response);  // completed
    (phases == 1 ? by_viewer : by_viewer_two) = worker.state()->table;
    CHECK(worker.state()->mesh->vertices() == by_cli->mesh()->vertices());
  }
  REQUIRE(by_viewer);
  REQUIRE(by_viewer_two);

  REQUIRE(by_cli->num_elements() > scene.problem.mesh.num_elements());  // the cut added walls
  for (const auto& other : {by_session, by_session_two, by_viewer, by_viewer_two}) {
    CHECK(other->num_elements() == by_cli->num_elements());
    CHECK(other->region() == by_cli->region());
    CHECK(other->base_kinds() == by_cli->base_kinds());
    CHECK(other->columns() == by_cli->columns());
    CHECK(other->base_displacement() == by_cli->base_displacement());
    CHECK(other->base_traction() == by_cli->base_traction());
  }
  CHECK(by_session->mesh()->faces() == by_cli->mesh()->faces());
  std::remove(path.c_str());
}

TEST_CASE("the viewer precomputes a hierarchical scene on the H-LU and cuts it there", "[viewer][hmatrix]") {
  // docs/viewer.md: the viewer's table is on the scene's backend; a cut updates the kept H-LU
  // (docs/cutting.md, "On either backend"). The independent answer: the same two steps on the
  // dense table (CutSystemUpdate, as `bemsurg cut`), which the compressed one matches to its tolerance.
  const std::string body = R"({
    "mesh": {"generator": "box", "min": [-0.04, -0.04, 0.0], "max": [0.04, 0.04, 0.04], "divisions": [6, 6, 2]},
    "material": {"young_modulus": 3000.0, "poisson_ratio": 0.45, "density": 1000.0},
    "gravity": [0.0, 0.0, -9.81],
    "boundary_conditions": {"rules": [
      {"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]},
    "operating_region": {"box": {"min": [-0.041, -0.041, 0.02], "max": [0.041, 0.041, 0.041]}},
    "solver": )";
  const std::string path = write_temp("hmatrix.json", body + R"({"method": "hmatrix", "compression_tolerance": 1e-8}})");
  const Scene dense_scene = load_scene_from_string(body + R"({"method": "lu"}})", ".", "dense");
  const Eigen::Vector3d from(-0.015, 0.0, 0.04), direction = Eigen::Vector3d::UnitX();
  CutSystemUpdate dense(std::make_shared<const GreensTable>(compute_scene_table(dense_scene)));
  dense.begin_cut();
  for (int i = 0; i < 2; ++i) REQUIRE(dense.cut(from, direction).accepted);
  dense.wait_for_refactor();

  ModelWorker worker;
  worker.load(path);
  worker.wait_idle();
  if (!hierarchical_backend_available()) {
    CHECK_THAT(worker.status().error, Catch::Contains("without hmat-oss"));
    std::remove(path.c_str());
    return;
  }
  REQUIRE(worker.status().error.empty());
  REQUIRE(worker.state()->table);
  CHECK(worker.state()->table->key().backend == SolverBackend::HMatrix);
  for (int i = 0; i < 2; ++i) worker.request_cut_step(i == 0, from, direction, 0.0);
  worker.wait_idle();
  REQUIRE(worker.status().cut_steps_accepted == 2);
  const std::shared_ptr<const GreensTable> cut = worker.state()->table;
  CHECK(cut->key().backend == SolverBackend::HMatrix);
  REQUIRE(cut->num_elements() == dense.table()->num_elements());
  REQUIRE(cut->region() == dense.table()->region());
  CHECK(max_relative(cut->columns(), dense.table()->columns()) <= 1e-6);
  CHECK(max_relative(cut->base_displacement(), dense.table()->base_displacement()) <= 1e-6);
  std::remove(path.c_str());
}
