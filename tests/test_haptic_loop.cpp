// Tests for the haptic loop and scripted sessions (haptics/haptic_loop.hpp, haptics/session.hpp;
// docs/haptics.md): forces equal the contact model's computed directly, each safety stage
// triggers when provoked, the loop never sees a half-swapped model, it shuts down with zero force,
// and its tick allocates nothing. Timing is measured in benchmarks/bench_haptic_loop.cpp, not here:
// these tests assert behaviour (forces, statuses, counts) and hold on a loaded machine.
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

#include "bemsurg/error.hpp"
#include "bemsurg/haptics/haptic_loop.hpp"
#include "bemsurg/haptics/recording_device.hpp"
#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/haptics/session.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "support/allocation_counter.hpp"
#include "support/temp_dir.hpp"

using namespace bemsurg;
using namespace bemsurg::haptics;
using Vec3 = Eigen::Vector3d;

namespace {

// A 1 x 1 x 0.5 block held at the bottom, soft (E = 2 kPa) so millimetre presses give newtons.
struct Block {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  Block() {
    auto m = std::make_shared<TriangleMesh>(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 6, 6, 3));
    std::vector<Index> bottom;
    for (Index e = 0; e < m->num_elements(); ++e)
      if (m->normal(e).z() < -0.99) bottom.push_back(e);
    const Material material{2000.0, 0.3, 1000.0};
    table = std::make_shared<const GreensTable>(
        GreensTable::compute(*m, material, supported_base_conditions(m->num_elements(), bottom)));
    mesh = m;
  }
};
Block& block() {
  static Block b;
  return b;
}

/// The same table with every compliance column scaled: a stiffer or softer body on the same mesh
/// (what a cut's new table is to the loop: a different snapshot of the same shape).
std::shared_ptr<const GreensTable> scaled_table(const GreensTable& t, double factor) {
  return std::make_shared<const GreensTable>(t.key(), t.region(), t.base_displacement(), t.base_traction(), t.base_kinds(),
                                             Eigen::MatrixXd(factor * t.columns()));
}

/// A model with one point tool (bonded) engaged at the top centre and driven by channel 0.
std::unique_ptr<ContactModel> point_model(std::shared_ptr<const GreensTable> table, std::uint64_t version) {
  auto m = std::make_unique<ContactModel>();
  m->mesh = block().mesh;
  m->table = std::move(table);
  m->solver = std::make_unique<ToolContactSolver>(m->mesh, m->table, 30);
  const int t = m->solver->add_tool(ToolSpec::point());
  REQUIRE(m->solver->engage(t, Vec3(0.52, 0.47, 1.0), Vec3(0, 0, -1)));
  m->solver->update();
  m->tool_of_channel[0] = t;
  m->version = version;
  return m;
}

/// The force the model gives for the device at `position` (computed directly, no loop).
Vec3 direct_point_force(const std::shared_ptr<const GreensTable>& table, const Vec3& position) {
  auto m = point_model(table, 1);
  m->solver->set_translation(0, position - m->solver->origin(0));
  m->solver->update();
  return m->solver->force(0);
}

const char* kPressScript = R"({
  "format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
  "tools": [{"name": "punch", "shape": "flat", "radius": 0.3}],
  "actions": [
    {"time": 0.0, "tool": "punch", "type": "move", "to": [0.5, 0.5, 0.7], "duration": 0.02},
    {"time": 0.05, "tool": "punch", "type": "press", "at": [0.5, 0.5, 0.7], "direction": [0, 0, -1], "depth": 0.001, "duration": 0.2}
  ]
})";

struct Collect : SessionObserver {
  std::vector<TickSample> samples;
  std::vector<int> cuts;
  void on_sample(const TickSample& s) override { samples.push_back(s); }
  void on_cut(int index, const TriangleMesh&) override { cuts.push_back(index); }
};

}  // namespace

TEST_CASE("a scripted press gives the force curve the contact model computes directly", "[haptics][session]") {
  Block& b = block();
  SessionOptions options;
  options.virtual_clock = true;
  Session session(b.mesh, b.table, load_action_script_from_string(kPressScript), options);
  Collect c;
  const SessionResult r = session.run(&c);
  REQUIRE(c.samples.size() == r.loop.ticks);
  CHECK(r.loop.ticks == 351);  // 0 .. 0.35 s (the last action ends at 0.25 s, + 0.1 s) at 1 kHz
  CHECK(r.loop.faults == 0);
  CHECK(r.loop.clamped_ticks == 0);  // the ramp is slow: the limiter passes the model's force
  // The reference: the flat punch placed on the same axis and moved to the device position.
  ToolContactSolver ref(b.mesh, b.table, 300);
  ToolSpec spec = ToolSpec::flat(0.3);
  spec.slide_margin = 0.3;
  const int t = ref.add_tool(spec);
  ref.place(t, Vec3(0.5, 0.5, 0.7), Vec3(0, 0, -1));
  double worst = 0.0, peak = 0.0;
  int compared = 0;
  for (std::size_t i = 0; i < c.samples.size(); i += 7) {
    const ChannelSample& s = c.samples[i].channel[0];
    ref.set_translation(t, s.position - Vec3(0.5, 0.5, 0.7));
    ref.update();
    const Vec3 F = ref.force(t);
    peak = std::max(peak, F.norm());
    worst = std::max(worst, (s.model_force - F).norm());
    worst = std::max(worst, (s.force - F).norm());  // nothing clamped: the device got the same
    ++compared;
  }
  INFO("peak force " << peak << " N, worst difference " << worst << " N over " << compared << " samples");
  CHECK(peak > 0.5);                  // the press is felt: 2.35 N at 1 mm
  CHECK(worst <= 1e-9 * peak);        // the loop renders exactly the model's force
  CHECK(c.samples.back().channel[0].contact_elements > 0);
}

TEST_CASE("a force above the device limit is clamped to 3.3 N and ramps at the rate limit", "[haptics][safety]") {
  NullDevice device(10.0);
  HapticLoopSettings settings;  // 3.3 N, 300 N/s
  HapticLoop loop(settings, {&device});
  auto m = point_model(block().table, 1);
  loop.offer(m);
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.2);  // deep: tens of newtons
  device.set_state(s);
  const double dt = 1e-3;
  double last = 0.0;
  for (int k = 0; k < 100; ++k) {
    loop.tick(k * dt);
    loop.heartbeat();
    const double f = device.last_force().norm();
    CHECK(f <= 3.3 * (1 + 1e-12));
    CHECK(std::abs(f - last) <= 300.0 * dt * (1 + 1e-9) + 1e-15);
    last = f;
  }
  TickSample sample;
  REQUIRE(loop.latest(sample));
  CHECK(sample.channel[0].model_force.norm() > 10.0);  // what the model asked for
  CHECK(device.last_force().norm() == Approx(3.3));
  CHECK(loop.statistics().clamped_ticks > 0);
}

TEST_CASE("a non-finite pose or force never reaches the device", "[haptics][safety]") {
  Block& b = block();
  NullDevice device;
  HapticLoop loop(HapticLoopSettings{}, {&device});
  // A table whose base traction is NaN on every element: the model's force is NaN.
  Eigen::VectorXd bad = b.table->base_traction();
  bad.setConstant(std::numeric_limits<double>::quiet_NaN());
  auto nan_table = std::make_shared<const GreensTable>(b.table->key(), b.table->region(), b.table->base_displacement(), bad,
                                                       b.table->base_kinds(), b.table->columns());
  auto good = point_model(b.table, 1);
  loop.offer(good);
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  device.set_state(s);
  for (int k = 0; k < 50; ++k) loop.tick(k * 1e-3);
  const Vec3 held = device.last_force();
  REQUIRE(held.norm() > 0.0);
  // NaN pose: refused, the force holds.
  s.position.x() = std::numeric_limits<double>::quiet_NaN();
  device.set_state(s);
  loop.tick(0.050);
  TickSample sample;
  REQUIRE(loop.latest(sample));
  CHECK(sample.channel[0].status == ContactStatus::NonFinitePose);
  CHECK(device.last_force().allFinite());
  CHECK((device.last_force() - held).norm() < 1e-12);
  // NaN force from the model: the last good force is sent instead.
  s.position.x() = 0.52;
  device.set_state(s);
  auto poisoned = point_model(nan_table, 2);
  loop.offer(poisoned);
  for (int k = 51; k < 60; ++k) loop.tick(k * 1e-3);
  CHECK(loop.statistics().nan_guards >= 9);
  CHECK(device.last_force().allFinite());
  CHECK((device.last_force() - held).norm() < 1e-12);
}

TEST_CASE("the watchdog ramps the force to zero on stale state and on repeated overruns", "[haptics][safety]") {
  Block& b = block();
  HapticLoopSettings settings;
  settings.stale_after_s = 0.1;
  settings.ramp_s = 0.05;
  settings.overrun_limit = 5;
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  SECTION("stale simulation state") {
    NullDevice device;
    device.set_state(s);
    HapticLoop loop(settings, {&device});
    auto m = point_model(b.table, 1);
    loop.offer(m);
    double at_stale = 0.0;
    for (int k = 0; k <= 200; ++k) {  // no heartbeat after the first tick
      loop.tick(k * 1e-3);
      if (k == 100) at_stale = device.last_force().norm();
    }
    CHECK(at_stale > 0.0);                      // full force until the state is 0.1 s old
    CHECK(device.last_force().norm() == 0.0);  // zero 0.05 s later, ramped
    // A fresh heartbeat brings the force back, ramping up.
    for (int k = 201; k <= 300; ++k) {
      loop.heartbeat();
      loop.tick(k * 1e-3);
    }
    CHECK(device.last_force().norm() == Approx(at_stale).epsilon(1e-9));
  }
  SECTION("repeated overruns") {
    NullDevice device;
    device.set_state(s);
    HapticLoop loop(settings, {&device});
    auto m = point_model(b.table, 1);
    loop.offer(m);
    for (int k = 0; k < 50; ++k) {
      loop.heartbeat();
      loop.tick(k * 1e-3);
    }
    const double full = device.last_force().norm();
    REQUIRE(full > 0.0);
    for (int k = 50; k < 54; ++k) {  // four late ticks: below the limit of five, no change
      loop.heartbeat();
      loop.tick(k * 1e-3, true);
    }
    CHECK(device.last_force().norm() == Approx(full));
    for (int k = 54; k < 120; ++k) {
      loop.heartbeat();
      loop.tick(k * 1e-3, true);
    }
    CHECK(device.last_force().norm() == 0.0);
    CHECK(loop.statistics().overruns == 70);
    CHECK(loop.statistics().watchdog_ticks > 0);
  }
}

TEST_CASE("a disconnected device gets zero force at once", "[haptics][safety]") {
  NullDevice device;
  HapticLoop loop(HapticLoopSettings{}, {&device});
  auto m = point_model(block().table, 1);
  loop.offer(m);
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  device.set_state(s);
  for (int k = 0; k < 30; ++k) loop.tick(k * 1e-3);
  REQUIRE(device.last_force().norm() > 0.0);
  s.connected = false;
  device.set_state(s);
  loop.tick(0.030);
  CHECK(device.last_force() == Vec3::Zero());
}

TEST_CASE("the loop thread starts and stops with zero force sent", "[haptics][loop]") {
  NullDevice device;
  HapticLoop loop(HapticLoopSettings{}, {&device});
  auto m = point_model(block().table, 1);
  loop.offer(m);
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  device.set_state(s);
  loop.start();
  CHECK(device.writes() >= 1);  // zero force first
  // Wait (generously: the machine may be loaded) until the loop has rendered a force.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  TickSample sample;
  bool felt = false;
  while (!felt && std::chrono::steady_clock::now() < deadline) {
    loop.heartbeat();
    if (loop.latest(sample)) felt = sample.channel[0].force.norm() > 0.0;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  CHECK(felt);
  loop.stop();
  CHECK(!loop.running());
  CHECK(device.last_force() == Vec3::Zero());
  CHECK(loop.statistics().ticks > 0);
  CHECK(loop.statistics().faults == 0);
  loop.stop();  // idempotent
}

TEST_CASE("model swaps under a running loop are whole: every force is the old or the new model's", "[haptics][loop]") {
  // Two snapshots of the table (the second twice as soft, as after a cut) offered alternately while
  // the loop runs: each sample's force must be exactly the force of the model version it reports.
  Block& b = block();
  const auto soft = scaled_table(*b.table, 2.0);
  const Vec3 pos = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  const Vec3 F_stiff = direct_point_force(b.table, pos), F_soft = direct_point_force(soft, pos);
  REQUIRE((F_stiff - F_soft).norm() > 0.1 * F_stiff.norm());
  NullDevice device(100.0);
  HapticLoopSettings settings;
  settings.max_force = 100.0;
  HapticLoop loop(settings, {&device});
  DeviceState s;
  s.position = pos;
  device.set_state(s);
  std::uint64_t version = 1;
  auto first = point_model(b.table, version);
  loop.offer(first);
  loop.start();
  int offered = 1;
  long checked = 0, wrong = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (offered < 40 && std::chrono::steady_clock::now() < deadline) {
    loop.heartbeat();
    if (!loop.offer_pending()) {
      ++version;
      auto m = point_model(version % 2 ? b.table : soft, version);
      if (loop.offer(m)) ++offered;
    }
    while (loop.take_retired()) {
    }
    TickSample t;
    while (loop.pop_sample(t)) {
      if (t.model_version == 0) continue;
      const Vec3& expect = t.model_version % 2 ? F_stiff : F_soft;
      if ((t.channel[0].model_force - expect).norm() > 1e-9 * expect.norm()) ++wrong;
      ++checked;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  loop.stop();
  CHECK(offered == 40);
  CHECK(checked > 0);
  CHECK(wrong == 0);
  CHECK(loop.statistics().model_swaps >= 2);
}

TEST_CASE("a cut through the session hook swaps the new table in between ticks", "[haptics][session][cut]") {
  Block& b = block();
  const char* script = R"({
    "format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
    "tools": [{"name": "grasper", "shape": "pinch"}, {"name": "scalpel", "shape": "blade"}],
    "actions": [
      {"time": 0.0, "tool": "grasper", "type": "pinch", "at": [0.52, 0.47, 0.7], "direction": [0, 0, -1]},
      {"time": 0.0, "tool": "grasper", "type": "move", "to": [0.52, 0.47, 0.501], "duration": 0.05},
      {"time": 0.1, "tool": "scalpel", "type": "cut", "from": [0.2, 0.2, 0.5], "direction": [1, 0, 0], "steps": 1}
    ]
  })";
  SessionOptions options;
  options.virtual_clock = true;
  const auto soft = scaled_table(*b.table, 2.0);
  int calls = 0;
  SECTION("without a hook the script is refused, naming the cut") {
    CHECK_THROWS_WITH(Session(b.mesh, b.table, load_action_script_from_string(script), options),
                      Catch::Contains("the cut of tool 'scalpel' at t = 0.1") && Catch::Contains("not wired"));
  }
  SECTION("with a hook") {
    options.cut_hook = [&](const CutRequest& r) {
      ++calls;
      CHECK(r.table == b.table);  // the current snapshot
      return CutResult{r.mesh, soft};
    };
    Session session(b.mesh, b.table, load_action_script_from_string(script), options);
    Collect c;
    const SessionResult r = session.run(&c);
    CHECK(calls == 1);
    CHECK(r.cuts == 1);
    CHECK(c.cuts == std::vector<int>{1});
    // Pulling up by 1 mm (the pinch grabbed the top at z = 0.5) at the end, before and after the cut.
    const Vec3 pos(0.52, 0.47, 0.501);
    auto pinch_force = [&](const std::shared_ptr<const GreensTable>& t) {
      ToolContactSolver s(b.mesh, t, 30);
      const int id = s.add_tool(ToolSpec::pinch());
      REQUIRE(s.engage(id, Vec3(0.52, 0.47, 0.7), Vec3(0, 0, -1)));
      s.set_translation(id, pos - s.origin(id));
      s.update();
      return Vec3(s.force(id));
    };
    const Vec3 before = pinch_force(b.table), after = pinch_force(soft);
    const std::uint64_t first_version = c.samples.front().model_version;
    long olds = 0, news = 0, neither = 0;
    for (const TickSample& t : c.samples) {
      if (t.time < 0.06) continue;  // still moving
      const Vec3& f = t.channel[0].model_force;
      if ((f - before).norm() <= 1e-9 * before.norm()) ++olds;
      else if ((f - after).norm() <= 1e-9 * after.norm()) ++news;
      else ++neither;
      if (t.time > 0.1 + 0.01) CHECK(t.model_version > first_version);
    }
    CHECK(olds > 0);
    CHECK(news > 0);
    CHECK(neither == 0);
  }
}

TEST_CASE("two devices drive two tools at once", "[haptics][session]") {
  Block& b = block();
  const char* script = R"({
    "format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
    "tools": [{"name": "punch", "shape": "flat", "radius": 0.2},
              {"name": "grasper", "shape": "pinch", "device": 1}],
    "actions": [
      {"time": 0.0, "tool": "punch", "type": "press", "at": [0.3, 0.3, 0.7], "direction": [0, 0, -1], "depth": 0.002, "duration": 0.05},
      {"time": 0.0, "tool": "grasper", "type": "pinch", "at": [0.75, 0.7, 0.7], "direction": [0, 0, -1]},
      {"time": 0.0, "tool": "grasper", "type": "move", "to": [0.75, 0.7, 0.502], "duration": 0.05}
    ]
  })";
  SessionOptions options;
  options.virtual_clock = true;
  Session session(b.mesh, b.table, load_action_script_from_string(script), options);
  Collect c;
  session.run(&c);
  const TickSample& last = c.samples.back();
  CHECK(last.channel[0].force.z() > 0.05);   // the punch is pushed up by the body
  CHECK(last.channel[1].force.z() < -0.05);  // the grasper is pulled down: the tissue resists
  CHECK(last.channel[0].contact_elements > 0);
  CHECK(last.channel[1].contact_elements == 1);
}

TEST_CASE("a recorded session replays the same poses", "[haptics][devices]") {
  bemsurg_test::TempDir dir("bemsurg_haptic_");
  std::vector<Keyframe> k(3);
  k[0].time = 0.0;
  k[1].time = 0.1;
  k[1].position = Vec3(0.01, 0.02, -0.03);
  k[1].buttons = 1;
  k[2].time = 0.1;  // a jump at 0.1 s
  k[2].position = Vec3(0.5, 0, 0);
  k[2].buttons = 3;
  RecordingDevice rec(std::make_unique<ScriptedDevice>(k), 1000);
  for (int i = 0; i <= 150; ++i) {
    rec.read(i * 1e-3);
    rec.write_force(Vec3(i, 0, 0));
  }
  CHECK(rec.samples().size() == 151);
  const std::string path = dir.file("rec.csv");
  rec.write_csv(path);
  ScriptedDevice replay(ScriptedDevice::read_csv(path));
  for (int i = 0; i <= 150; ++i) {
    const DeviceState a = rec.samples()[static_cast<std::size_t>(i)].state, r = replay.read(i * 1e-3);
    CHECK((a.position - r.position).norm() < 1e-15);
    CHECK(a.buttons == r.buttons);
  }
  CHECK(replay.read(0.05).position.isApprox(Vec3(0.005, 0.01, -0.015)));
  CHECK(replay.read(0.1).buttons == 3U);
  CHECK_THROWS_WITH(ScriptedDevice::read_csv(dir.file("missing.csv")), Catch::Contains("cannot open"));
}

TEST_CASE("a haptic tick allocates nothing", "[haptics][loop]") {
  NullDevice device;
  HapticLoop loop(HapticLoopSettings{}, {&device});
  auto m = point_model(block().table, 1);
  loop.offer(m);
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  device.set_state(s);
  loop.tick(0.0);  // takes the model
  TickSample sample;
  const long n = bemsurg_test::allocations_during([&] {
    for (int k = 1; k < 200; ++k) {
      s.buttons = (k / 10) % 2;  // button edges go to the event ring
      device.set_state(s);
      loop.tick(k * 1e-3);
      loop.pop_sample(sample);
    }
  });
  CHECK(n == 0);
  CHECK(sample.channel[0].force.norm() > 0.0);
}
