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
#include "bemsurg/haptics/model_crossfade.hpp"
#include "bemsurg/haptics/recording_device.hpp"
#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/haptics/session.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "support/allocation_counter.hpp"
#include "support/half_space_table.hpp"
#include "support/haptic_block.hpp"
#include "support/temp_dir.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;
using namespace bemsurg::haptics;
using Vec3 = Eigen::Vector3d;

namespace {

// Round-off bounds of the form c n eps: a force from the contact model is a solve with the
// capacitance block G_CC of its rows, whose condition number is at most about 30 on this mesh
// (tests/test_contact_capacitance.cpp: 1.5, 6.6, 27 for 1, 7, 50 bonded elements).
using bemsurg_test::kEps;
constexpr double kCond = 30.0;

using Block = testing::HapticBlock;
Block& block() { return testing::haptic_block(); }
using testing::scaled_table;

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
  Index rows = 0;
  for (std::size_t i = 0; i < c.samples.size(); i += 7) {
    const ChannelSample& s = c.samples[i].channel[0];
    ref.set_translation(t, s.position - Vec3(0.5, 0.5, 0.7));
    ref.update();
    const Vec3 F = ref.force(t);
    rows = std::max(rows, ref.contact().num_rows());
    peak = std::max(peak, F.norm());
    worst = std::max(worst, (s.model_force - F).norm());
    worst = std::max(worst, (s.force - F).norm());  // nothing clamped: the device got the same
    ++compared;
  }
  INFO("peak force " << peak << " N, worst difference " << worst << " N over " << compared << " samples");
  CHECK(peak > 0.78);  // the press is felt: measured 2.35 N at 1 mm, bound a third of it
  // The loop renders exactly the model's force: measured 0; bound 2 kCond rows eps (the loop's
  // solver reaches the same contact set through other set changes than the reference).
  CHECK(worst <= 2.0 * kCond * rows * kEps * peak);
  CHECK(c.samples.back().channel[0].contact_elements > 0);
}

TEST_CASE("a force above the device limit is clamped to 3.3 N and ramps at the rate limit", "[haptics][safety]") {
  NullDevice device(10.0);
  HapticLoopOptions settings;  // 3.3 N, 300 N/s
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
    // The clip to 3.3 N is a scaling and a norm, a few roundings: 4 eps (measured: never above 3.3 N).
    CHECK(f <= 3.3 * (1 + 4 * kEps));
    // The change of the norm: both norms <= 3.3 N carry 2 eps each and the clipped step 2 eps of
    // 0.3 N: 8 eps x 3.3 N above the 0.3 N step (measured 7.3e-16 N above it).
    CHECK(std::abs(f - last) <= 300.0 * dt + 8 * kEps * 3.3);
    last = f;
  }
  TickSample sample;
  REQUIRE(loop.latest(sample));
  CHECK(sample.channel[0].model_force.norm() > 18.0);                  // what the model asked for: measured 55.4 N, bound a third
  CHECK(device.last_force().norm() == Approx(3.3).epsilon(4 * kEps));  // measured 1.1e-16 relative
  CHECK(loop.statistics().clamped_ticks > 0);
}

TEST_CASE("a non-finite pose or force never reaches the device", "[haptics][safety]") {
  Block& b = block();
  NullDevice device;
  HapticLoop loop(HapticLoopOptions{}, {&device});
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
  // Held: the limiter re-sends its last force, a zero step (measured 0; bound 4 eps |held|).
  CHECK((device.last_force() - held).norm() <= 4 * kEps * held.norm());
  // NaN force from the model: the last good force is sent instead.
  s.position.x() = 0.52;
  device.set_state(s);
  auto poisoned = point_model(nan_table, 2);
  loop.offer(poisoned);
  for (int k = 51; k < 60; ++k) loop.tick(k * 1e-3);
  CHECK(loop.statistics().nan_guards >= 9);
  CHECK(device.last_force().allFinite());
  CHECK((device.last_force() - held).norm() <= 4 * kEps * held.norm());  // measured 0
}

TEST_CASE("the watchdog ramps the force to zero on stale state and on repeated overruns", "[haptics][safety]") {
  Block& b = block();
  HapticLoopOptions settings;
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
    CHECK(at_stale > 0.0);                     // full force until the state is 0.1 s old
    CHECK(device.last_force().norm() == 0.0);  // zero 0.05 s later, ramped
    // A fresh heartbeat brings the force back, ramping up.
    for (int k = 201; k <= 300; ++k) {
      loop.heartbeat();
      loop.tick(k * 1e-3);
    }
    // The fade factor is back to 1 and the ramp's last step lands on the request: a few roundings
    // (measured 0).
    CHECK(device.last_force().norm() == Approx(at_stale).epsilon(4 * kEps));
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
    CHECK(device.last_force().norm() == Approx(full).epsilon(4 * kEps));  // measured 0
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
  HapticLoop loop(HapticLoopOptions{}, {&device});
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
  HapticLoop loop(HapticLoopOptions{}, {&device});
  auto m = point_model(block().table, 1);
  loop.offer(m);
  DeviceState s;
  s.position = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  device.set_state(s);
  loop.start();
  // Wait until the loop has rendered a force: a deadline, not a speed bound (one tick at 1 kHz
  // suffices; 20 s fails only a loop that never ticks, also under sanitizers).
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
  // One write per tick, plus zero force on start, at the thread's end and after the join.
  CHECK(device.writes() == static_cast<long>(loop.statistics().ticks) + 3);
  // Each trace entry carries its own tick's computation time: positive, and at most the loop's
  // force-time maximum (the same tick's, measured a little later: after the trace push).
  TickSample traced;
  int entries = 0;
  while (loop.pop_sample(traced)) {
    ++entries;
    CHECK(traced.compute_us > 0.0);
    CHECK(traced.compute_us <= loop.statistics().force_us.max);
  }
  CHECK(entries > 0);
  loop.stop();  // idempotent
  CHECK(device.writes() == static_cast<long>(loop.statistics().ticks) + 3);
}

TEST_CASE("model swaps under a running loop are whole: the model force is the new model's, the force sent the reported blend",
          "[haptics][loop]") {
  // Two snapshots of the table (the second twice as soft, as after a cut) offered alternately while
  // the loop runs: each sample's model force must be exactly the force of the model version it
  // reports, and the force sent, during a blend, the mix (1 - w) old + w new with the weight w the
  // sample reports (the old model is always the version before: an offer waits until the blend ends).
  Block& b = block();
  const auto soft = scaled_table(*b.table, 2.0);
  const Vec3 pos = Vec3(0.52, 0.47, 0.5) + Vec3(0, 0, -0.001);
  const Vec3 F_stiff = direct_point_force(b.table, pos), F_soft = direct_point_force(soft, pos);
  // Twice the compliance halves a bonded point's force (no base traction): measured exactly 0.5;
  // bound a third of it.
  REQUIRE((F_stiff - F_soft).norm() > 0.16 * F_stiff.norm());
  NullDevice device(100.0);
  HapticLoopOptions settings;
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
  long checked = 0, wrong = 0, blended = 0;
  // A deadline, not a speed bound: 40 offers take the loop about 40 ticks (40 ms at 1 kHz) plus the
  // model builds (milliseconds), so 30 s fails only a loop that stopped taking models.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (offered < 40 && std::chrono::steady_clock::now() < deadline) {
    loop.heartbeat();
    if (!loop.offer_pending()) {
      ++version;
      auto m = point_model(version % 2 ? b.table : soft, version);
      if (loop.offer(m)) ++offered;
    }
    while (loop.take_retired()) {}
    TickSample t;
    while (loop.pop_sample(t)) {
      if (t.model_version == 0) continue;
      const Vec3& now = t.model_version % 2 ? F_stiff : F_soft;
      const Vec3& old = t.model_version % 2 ? F_soft : F_stiff;
      // The same model at the same position (measured 0): a bonded point's 3 rows, kCond 3 eps.
      if ((t.channel[0].model_force - now).norm() > kCond * 3 * kEps * now.norm()) ++wrong;
      // Sent: the mix by the reported weight (the rate limiter does not act: the models differ by
      // well under 0.3 N per 1/30 of the blend), with the mix's few roundings.
      const Vec3 sent = t.blend_weight < 1.0 ? ModelCrossfade::mix(old, now, t.blend_weight) : now;
      if (t.watchdog_gain == 1.0 && (t.channel[0].force - sent).norm() > kCond * 3 * kEps * (F_stiff.norm() + F_soft.norm())) ++wrong;
      blended += t.blend_weight < 1.0 ? 1 : 0;
      ++checked;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  loop.stop();
  CHECK(offered == 40);
  CHECK(checked > 0);
  CHECK(wrong == 0);
  CHECK(blended > 0);
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
      {"time": 0.1, "tool": "scalpel", "type": "cut", "from": [0.2, 0.2, 0.5], "direction": [1, 0, 0], "steps": 2, "step_interval": 0.05}
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
    int prepared = 0;
    options.cut_prepare = [&](const std::shared_ptr<const GreensTable>& t) {
      CHECK(calls == 0);  // before the first step
      CHECK(t == b.table);
      ++prepared;
    };
    options.cut_hook = [&](const CutRequest& r) {
      CHECK(prepared == 1);
      ++calls;
      CHECK(r.step == calls - 1);
      CHECK(r.table == (calls == 1 ? b.table : soft));  // the current snapshot
      return CutResult{r.mesh, soft};
    };
    Session session(b.mesh, b.table, load_action_script_from_string(script), options);
    Collect c;
    const SessionResult r = session.run(&c);
    CHECK(prepared == 1);
    CHECK(calls == 2);
    CHECK(r.cuts == 2);
    CHECK(c.cuts == std::vector<int>{1, 2});
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
    long olds = 0, news = 0, mixed = 0, neither = 0;
    const double tol = kCond * 3 * kEps;  // a bonded pinch on one element, 3 rows (measured 0)
    double largest_step = 0.0;
    Vec3 last = Vec3::Zero();
    for (const TickSample& t : c.samples) {
      if (t.time < 0.06) continue;  // still moving
      const Vec3& f = t.channel[0].model_force;
      if ((f - before).norm() <= tol * before.norm())
        ++olds;
      else if ((f - after).norm() <= tol * after.norm())
        ++news;
      else
        ++neither;
      // What was sent: the old model's force blended into the new one's by the reported weight.
      const Vec3& sent = t.channel[0].force;
      if (t.time > 0.0605) largest_step = std::max(largest_step, (sent - last).norm());
      last = sent;
      if (t.blend_weight < 1.0 && (f - after).norm() <= tol * after.norm() && (sent - after).norm() > tol * after.norm()) {
        ++mixed;
        CHECK((sent - ModelCrossfade::mix(before, after, t.blend_weight)).norm() <= tol * (before.norm() + after.norm()));
      }
      if (t.time > 0.1 + 0.01) CHECK(t.model_version > first_version);
    }
    CHECK(olds > 0);
    CHECK(news > 0);
    CHECK(neither == 0);
    // The first cut's swap blends over blend_s (30 ticks at 1 kHz: weight 0, 1/30, ..., 29/30);
    // the second step's table is the same, so its blend mixes equal forces.
    CHECK(mixed == 30);
    // No tick moves the force sent by more than the models' difference / 30 (+ round-off).
    CHECK(largest_step <= (after - before).norm() / 30.0 * (1.0 + 1e-9));
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
  CHECK(last.channel[0].force.z() > 0.74);   // the punch is pushed up by the body: measured 2.24 N, bound a third
  CHECK(last.channel[1].force.z() < -0.17);  // the grasper is pulled down, the tissue resists: measured -0.537 N
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
    CHECK((a.position - r.position).norm() < 1e-15);  // measured 0 (round-trip text); bound ~9 eps at |x| <= 0.5
    CHECK(a.buttons == r.buttons);
  }
  CHECK(replay.read(0.05).position.isApprox(Vec3(0.005, 0.01, -0.015), 4 * kEps));  // halfway: measured 0
  CHECK(replay.read(0.1).buttons == 3U);
  CHECK_THROWS_WITH(ScriptedDevice::read_csv(dir.file("missing.csv")), Catch::Contains("cannot open"));
}

TEST_CASE("a haptic tick allocates nothing", "[haptics][loop]") {
  NullDevice device;
  HapticLoop loop(HapticLoopOptions{}, {&device});
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

TEST_CASE("an action script becomes keyframes: a press starts at first contact and pushes its depth", "[haptics][session]") {
  Block& b = block();
  const Session session(b.mesh, b.table, load_action_script_from_string(kPressScript), SessionOptions{});
  const ScriptedDevice d(session.keyframes(0));
  // The move holds at its target; the press jumps to where the disc first touches the top (z = 0.5)
  // and pushes 1 mm over 0.2 s, linearly; after the script the tool stays where it ended. Measured
  // 0 to 8.9e-16 (below: the first contact comes from a ray cast from z = 2); bound 16 eps, the
  // ray's rounding at lengths <= 2 plus the interpolation's.
  const double tol = 16 * kEps;
  CHECK((d.state_at(0.04).position - Vec3(0.5, 0.5, 0.7)).norm() < tol);
  CHECK(std::abs(d.state_at(0.05).position.z() - 0.5) < tol);
  CHECK(std::abs(d.state_at(0.15).position.z() - 0.4995) < tol);
  CHECK(std::abs(d.state_at(0.25).position.z() - 0.499) < tol);
  CHECK(std::abs(d.state_at(10.0).position.z() - 0.499) < tol);
  CHECK(d.state_at(0.1).buttons == 0U);  // a flat tool needs no button
  const char* pinch = R"({"format": "bemsurg-actions", "version": 1,
    "tools": [{"name": "g", "shape": "pinch"}],
    "actions": [{"time": 0.1, "tool": "g", "type": "pinch", "at": [0.3, 0.3, 2.0], "direction": [0, 0, -1]},
                {"time": 0.2, "tool": "g", "type": "release"}]})";
  const Session ps(b.mesh, b.table, load_action_script_from_string(pinch), SessionOptions{});
  const ScriptedDevice g(ps.keyframes(0));
  CHECK(g.state_at(0.05).buttons == 0U);
  CHECK(g.state_at(0.15).buttons == 1U);                       // the jaws close: button 0 held
  CHECK(std::abs(g.state_at(0.15).position.z() - 0.5) < tol);  // measured 8.9e-16
  CHECK(g.state_at(0.25).buttons == 0U);
}

TEST_CASE("the workspace maps device positions into the model and forces back", "[haptics][devices]") {
  NullDevice device;
  Workspace w;
  w.scale = 2.0;
  w.offset = Vec3(0.5, 0.5, 0.0);
  w.force_scale = 0.5;
  HapticLoop loop(HapticLoopOptions{}, {&device}, {w});
  auto m = point_model(block().table, 1);
  loop.offer(m);
  DeviceState s;
  s.position = Vec3(0.01, -0.015, 0.2495);  // model: (0.52, 0.47, 0.499), 1 mm into the top
  device.set_state(s);
  for (int k = 0; k < 30; ++k) loop.tick(k * 1e-3);
  TickSample sample;
  REQUIRE(loop.latest(sample));
  CHECK((sample.channel[0].position - Vec3(0.52, 0.47, 0.499)).norm() < 4 * kEps);  // a scale and an offset: measured 0
  const Vec3 F = direct_point_force(block().table, Vec3(0.52, 0.47, 0.499));
  CHECK((sample.channel[0].model_force - F).norm() < kCond * 3 * kEps * F.norm());             // bonded point, 3 rows: measured 0
  CHECK((device.last_force() - 0.5 * sample.channel[0].force).norm() <= 4 * kEps * F.norm());  // x 0.5: measured 0
}

TEST_CASE("a sphere sliding at constant depth does not click at element boundaries", "[haptics][session][continuity]") {
  // docs/haptics.md "Force continuity": R = 10 mm, 1 mm deep, 10 mm/s, over 4 mm elements (the
  // coarse model of bench_haptic_loop --quick; the half-space stand-in table): the largest change
  // between consecutive 1 kHz samples, relative to the force, must stay under 5 %. Measured 1.96 %
  // (the full benchmark, 1 mm elements: 2.36 %); bound 2.8 %.
  const HalfSpaceBlock model = half_space_block(0.004, 0.025, 0.008, 0.012, Material{1.0e5, 0.45, 1000.0});
  const char* script = R"({"format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
    "tools": [{"name": "probe", "shape": "sphere", "radius": 0.010}],
    "actions": [
      {"time": 0.0, "tool": "probe", "type": "press", "at": [-0.005, -0.002, 0.02], "direction": [0, 0, -1], "depth": 0.001, "duration": 0.3},
      {"time": 0.3, "tool": "probe", "type": "move", "to": [0.005, -0.002, 0.009], "duration": 1.0}]})";
  SessionOptions options;
  options.virtual_clock = true;
  Session session(model.mesh, model.table, load_action_script_from_string(script), options);
  Collect c;
  const SessionResult r = session.run(&c);
  INFO("largest jump " << 100 * r.max_force_jump_fraction << " % at t = " << r.max_force_jump_time << " s, peak " << r.peak_force[0]
                       << " N, " << r.models_built << " models");
  CHECK(r.peak_force[0] > 0.3);  // the sphere is pressing (0.52 N measured)
  CHECK(r.models_built >= 2);    // it was placed again while sliding
  CHECK(r.max_force_jump_fraction < 0.028);
  // While sliding (t > 0.35 s) the force stays within 20 % of its mean: constant depth, constant force.
  double lo = 1e300, hi = 0.0;
  for (const TickSample& t : c.samples)
    if (t.time > 0.35 && t.time < 1.3) {
      lo = std::min(lo, t.channel[0].model_force.norm());
      hi = std::max(hi, t.channel[0].model_force.norm());
    }
  CHECK(hi > 0.0);
  CHECK(hi - lo < 0.2 * hi);  // measured 0.075 hi
}
