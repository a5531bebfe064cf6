// Feeling through a cut (issue 26; docs/haptics.md, "Long steps" and "Model swaps"): a cut step
// that computes for longer than the watchdog's stale_after_s no longer fades the force, because
// the step runs on a background thread while the simulation side keeps beating; the watchdog still
// fades the force when the simulation side is really gone (its thread stopped, or a step hung);
// the session's metrics see a fade; background work gets cores - 1 threads. Real-time cases on the
// small block of test_haptic_loop.cpp: they assert forces and counts, never speed, so they hold on
// a loaded machine and under the sanitizers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif
#include "bemsurg/blas_threads.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/haptics/background_task.hpp"
#include "bemsurg/haptics/felt_force.hpp"
#include "bemsurg/haptics/haptic_loop.hpp"
#include "bemsurg/haptics/session.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "support/haptic_block.hpp"

// OpenBLAS's own setter (weak: null where the BLAS is not OpenBLAS), to give the caps a pool to cap.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

using namespace bemsurg;
using namespace bemsurg::haptics;
using Vec3 = Eigen::Vector3d;

namespace {

using Block = testing::HapticBlock;  // the block of test_haptic_loop.cpp (same cached table)

// A pinch pulls the top 1 mm up (slowly: 400 ticks, so no tick of the pull itself changes the force
// by more than 2.5 % of it above 10 % of the peak) and holds it while two cut steps run; each step
// "computes" for `seconds` (longer than stale_after_s 0.25 s) and returns the table 1 % softer.
const char* kHoldScript = R"({
  "format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
  "tools": [{"name": "grasper", "shape": "pinch"}, {"name": "scalpel", "shape": "blade", "device": 1}],
  "actions": [
    {"time": 0.0, "tool": "grasper", "type": "pinch", "at": [0.52, 0.47, 0.7], "direction": [0, 0, -1]},
    {"time": 0.0, "tool": "grasper", "type": "move", "to": [0.52, 0.47, 0.501], "duration": 0.4},
    {"time": 0.45, "tool": "scalpel", "type": "cut", "from": [0.2, 0.2, 0.5], "direction": [1, 0, 0], "steps": 2, "step_interval": 0.05},
    {"time": 1.2, "tool": "grasper", "type": "release"}
  ]})";

CutHook slow_hook(double seconds) {
  // Captures by value only: a hung step's detached thread may outlive the test's locals.
  return [seconds](const CutRequest& r) {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    return CutResult{r.mesh, testing::scaled_table(*r.table, 1.01)};
  };
}

struct Trace : SessionObserver {
  std::vector<TickSample> samples;
  void on_sample(const TickSample& s) override { samples.push_back(s); }
};

}  // namespace

TEST_CASE("a cut step longer than the watchdog's staleness keeps the force: the simulation side stays alive", "[haptics][continuity]") {
  const Block& b = testing::haptic_block();
  SessionOptions options;
  options.cut_hook = slow_hook(0.4);
  options.loop.realtime_priority = 0;  // behaviour, not timing: the same at any priority
  SECTION("background steps (the default): no fade, every step made") {
    Session session(b.mesh, b.table, load_action_script_from_string(kHoldScript), options);
    Trace trace;
    const SessionResult r = session.run(&trace);
    CHECK(r.cuts == 2);
    REQUIRE(r.cut_step_seconds.size() == 2);
    CHECK(r.cut_step_seconds[0] >= 0.4);
    CHECK(r.loop.watchdog_ticks == 0);
    // While the pinch holds still and the two 1 % softer models are blended in (the trace, not the
    // whole-run metric: a slow machine, e.g. under the sanitizers, can engage the pinch late, and
    // the engagement's own blend then starts below the model force): the delivered force stays at
    // the model's, and no tick changes it by more than its share of the 1 % difference, dt / blend_s
    // of it (a late tick moves the weight by its own dt), where switching would move all of it.
    double hold_ratio = 1.0, hold_excess = 0.0, peak = 0.0;
    for (std::size_t k = 1; k < trace.samples.size(); ++k) {
      const TickSample &a = trace.samples[k - 1], &z = trace.samples[k];
      peak = std::max(peak, z.channel[0].model_force.norm());
      if (a.time <= 0.42 || z.time >= 1.2) continue;
      hold_ratio = std::min(hold_ratio, z.channel[0].force.norm() / z.channel[0].model_force.norm());
      const double allowed = 0.0101 * std::min(1.0, (z.time - a.time) / options.loop.blend_s) * z.channel[0].model_force.norm();
      hold_excess = std::max(hold_excess, (z.channel[0].force - a.channel[0].force).norm() / allowed);
    }
    REQUIRE(peak > 0.0);
    CHECK(hold_ratio > 0.98);
    CHECK(hold_excess <= 1.0);
  }
  SECTION("steps on the simulation thread (before): the watchdog fades the force, and the metric shows it") {
    options.background_steps = false;
    options.loop.blend_s = 0.0;
    Session session(b.mesh, b.table, load_action_script_from_string(kHoldScript), options);
    const SessionResult r = session.run();
    CHECK(r.cuts == 2);
    CHECK(r.loop.watchdog_ticks > 0);
    CHECK(r.felt.min_delivered_ratio < 0.1);  // 0.4 s without a heartbeat: faded to zero after 0.25 + 0.05 s
    CHECK(r.felt.min_delivered_ratio_time > 0.45);
    // The model force never moved under the cut: max_force_jump_fraction is blind to the fade. A larger
    // jump can only come from the pull before the cut, whose 2.5 % per tick doubles when the loaded
    // machine delivers a tick late (seen once: 5.3 % at the pull).
    INFO("largest model-force jump " << r.max_force_jump_fraction << " at t = " << r.max_force_jump_time << " s");
    CHECK((r.max_force_jump_fraction < 0.05 || r.max_force_jump_time < 0.42));
  }
}

TEST_CASE("a cut step answers first within the tools' reach, then completes before the next step", "[haptics][continuity][cut]") {
  // docs/haptics.md, "First response, then the complete table": the hook's first response (0.1 s
  // here, a table 1 % softer) is handed to the loop at once; its completion (0.3 s more, 2 % softer)
  // follows on the background thread, and the next step (due 0.05 s later) waits for it.
  struct Record {
    std::mutex lock;
    std::vector<double> requested, completed, reach;
    std::vector<std::size_t> tools;
    int completions = 0;
  };
  const auto record = std::make_shared<Record>();
  const auto start = std::chrono::steady_clock::now();
  const auto since = [start] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const Block& b = testing::haptic_block();
  SessionOptions options;
  options.loop.realtime_priority = 0;
  options.cut_hook = [record, since](const CutRequest& r) {
    {
      std::lock_guard<std::mutex> g(record->lock);
      record->requested.push_back(since());
      record->reach.push_back(r.reach);
      record->tools.push_back(r.tools.size());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    CutResult out{r.mesh, testing::scaled_table(*r.table, 1.01)};
    if (r.reach > 0.0) {
      const std::shared_ptr<const GreensTable> table = r.table;
      out.complete = [record, since, table] {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        std::lock_guard<std::mutex> g(record->lock);
        ++record->completions;
        record->completed.push_back(since());
        return testing::scaled_table(*table, 1.02);
      };
    }
    return out;
  };
  SECTION("two phases (the default)") {
    Session session(b.mesh, b.table, load_action_script_from_string(kHoldScript), options);
    const SessionResult r = session.run();
    CHECK(r.cuts == 2);
    REQUIRE(r.cut_step_seconds.size() == 2);
    REQUIRE(r.cut_complete_seconds.size() == 2);
    std::lock_guard<std::mutex> g(record->lock);
    CHECK(record->completions == 2);
    REQUIRE(record->requested.size() == 2);
    REQUIRE(record->completed.size() == 2);
    CHECK(record->requested[1] >= record->completed[0]);  // the next step waited for the completion
    CHECK(r.cut_steps_waited == 1);
    for (std::size_t i = 0; i < 2; ++i) {
      CHECK(record->reach[i] >= options.reach_margin);  // a 0-radius pinch and blade: the margin
      CHECK(record->tools[i] >= 3);                     // both tools' tips, where the pinch holds, the elements in contact
      CHECK(r.cut_step_seconds[i] >= 0.1);
      CHECK(r.cut_complete_seconds[i] >= r.cut_step_seconds[i] + 0.29);
    }
    CHECK(r.loop.watchdog_ticks == 0);
    CHECK(r.loop.model_swaps >= 4);  // each step's first response and its completion
  }
  SECTION("one phase: the hook is asked for the complete table at once") {
    options.first_response = false;
    Session session(b.mesh, b.table, load_action_script_from_string(kHoldScript), options);
    const SessionResult r = session.run();
    CHECK(r.cuts == 2);
    REQUIRE(r.cut_complete_seconds.size() == 2);
    CHECK(r.cut_complete_seconds == r.cut_step_seconds);
    std::lock_guard<std::mutex> g(record->lock);
    CHECK(record->completions == 0);
    for (double reach : record->reach) CHECK(reach == 0.0);
  }
}

TEST_CASE("a grasp made while a cut step completes waits for the complete table", "[haptics][continuity][cut]") {
  // The first response's table covers only the tools' reach; a pinch closing meanwhile on an element
  // outside it (engage refuses an element outside the table's region) used to end the session with
  // an error. It now waits for the complete table, and holds once that lands.
  const char* script = R"({
    "format": "bemsurg-actions", "version": 1, "rate_hz": 1000,
    "tools": [{"name": "grasper", "shape": "pinch", "start": [0.52, 0.47, 0.9]},
              {"name": "scalpel", "shape": "blade", "device": 1}],
    "actions": [
      {"time": 0.05, "tool": "scalpel", "type": "cut", "from": [0.2, 0.2, 0.5], "direction": [1, 0, 0], "steps": 1},
      {"time": 0.2, "tool": "grasper", "type": "pinch", "at": [0.52, 0.47, 0.7], "direction": [0, 0, -1]},
      {"time": 0.2, "tool": "grasper", "type": "move", "to": [0.52, 0.47, 0.501], "duration": 0.4},
      {"time": 1.1, "tool": "grasper", "type": "release"}
    ]})";
  const Block& b = testing::haptic_block();
  // The first response: the table over the elements left of x = 0.3 only (the grasp is at x = 0.52).
  std::vector<Index> near;
  for (Index e : b.table->region())
    if (b.mesh->centroid(e).x() < 0.3) near.push_back(e);
  Eigen::MatrixXd columns(b.table->num_dofs(), 3 * static_cast<Index>(near.size()));
  for (std::size_t i = 0; i < near.size(); ++i)
    columns.middleCols(3 * static_cast<Index>(i), 3) = b.table->columns().middleCols(3 * b.table->region_slot(near[i]), 3);
  const auto first = std::make_shared<const GreensTable>(b.table->key(), near, b.table->base_displacement(), b.table->base_traction(),
                                                         b.table->base_kinds(), columns);
  SessionOptions options;
  options.loop.realtime_priority = 0;
  const auto completions = std::make_shared<std::atomic<int>>(0);
  const auto asked_first = std::make_shared<std::atomic<bool>>(false);
  options.cut_hook = [first, completions, asked_first](const CutRequest& r) {  // runs on the background thread: no assertions
    asked_first->store(r.reach > 0.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::shared_ptr<const GreensTable> complete = r.table;
    return CutResult{r.mesh, first, [complete, completions] {
                       std::this_thread::sleep_for(std::chrono::milliseconds(600));
                       ++*completions;
                       return complete;
                     }};
  };
  Session session(b.mesh, b.table, load_action_script_from_string(script), options);
  SessionResult r;
  REQUIRE_NOTHROW(r = session.run());
  CHECK(r.cuts == 1);
  CHECK(asked_first->load());
  CHECK(*completions == 1);
  REQUIRE(r.peak_force.size() == 2);
  CHECK(r.peak_force[0] > 0.0);  // the grasp held once the complete table landed
}

TEST_CASE("the watchdog still fades the force when the simulation side is gone", "[haptics][continuity][safety]") {
  const Block& b = testing::haptic_block();
  SECTION("its thread stopped: zero force within stale_after_s + ramp_s of the last heartbeat") {
    NullDevice device(100.0);
    HapticLoopOptions settings;
    settings.realtime_priority = 0;
    settings.stale_after_s = 0.1;
    settings.ramp_s = 0.05;
    HapticLoop loop(settings, {&device});
    auto m = std::make_unique<ContactModel>();
    m->mesh = b.mesh;
    m->table = b.table;
    m->solver = std::make_unique<ToolContactSolver>(m->mesh, m->table, 30);
    const int t = m->solver->add_tool(ToolSpec::point());
    REQUIRE(m->solver->engage(t, Vec3(0.52, 0.47, 1.0), Vec3(0, 0, -1)));
    m->tool_of_channel[0] = t;
    m->version = 1;
    REQUIRE(loop.offer(m));
    DeviceState s;
    s.position = Vec3(0.52, 0.47, 0.499);
    device.set_state(s);
    std::atomic<bool> stop_simulation{false};
    std::atomic<double> last_beat{0.0};
    std::thread simulation([&] {  // beats at 250 Hz until stopped, as a session's simulation side
      while (!stop_simulation.load()) {
        loop.heartbeat();
        last_beat.store(loop.time());
        std::this_thread::sleep_for(std::chrono::milliseconds(4));
      }
    });
    loop.start();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);  // not a speed bound
    while (loop.time() < 0.3 && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    stop_simulation.store(true);  // the simulation side is gone
    simulation.join();
    const double gone = last_beat.load();
    while (loop.time() < gone + 0.4 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    loop.stop();
    double felt_before = 0.0, zero_at = -1.0;
    TickSample x;
    while (loop.pop_sample(x)) {
      if (x.time < gone) felt_before = x.channel[0].force.norm();
      if (x.time >= gone && zero_at < 0.0 && x.channel[0].force.norm() == 0.0) zero_at = x.time;
    }
    CHECK(felt_before > 0.0);
    REQUIRE(zero_at > 0.0);
    // The heartbeat is read each tick; stale after 0.1 s, ramped down over 0.05 s; one beat
    // period (4 ms) and a tick of slack.
    CHECK(zero_at - gone <= settings.stale_after_s + settings.ramp_s + 0.006);
    CHECK(zero_at - gone >= settings.stale_after_s);
  }
  SECTION("a hung step: the heartbeat stops, the force fades to zero, and the session ends with an error") {
    SessionOptions options;
    options.cut_hook = slow_hook(3.0);
    options.max_step_s = 0.2;
    options.loop.realtime_priority = 0;
    Session session(b.mesh, b.table, load_action_script_from_string(kHoldScript), options);
    Trace trace;
    CHECK_THROWS_WITH(session.run(&trace), Catch::Contains("taken as hung") && Catch::Contains("faded to zero"));
    REQUIRE(!trace.samples.empty());
    CHECK(trace.samples.back().watchdog_gain == 0.0);
    CHECK(trace.samples.back().channel[0].force.norm() == 0.0);
    CHECK(trace.samples.back().time < 0.45 + 0.2 + 0.25 + 0.05 + 0.1);  // hung at 0.65 s, faded 0.3 s later, then ended
  }
}

TEST_CASE("BLAS thread caps nest and overlap, the pool takes the smallest live one and gets back what it had", "[haptics][threads]") {
  // bemsurg/blas_threads.hpp: a haptic loop's budget and an H-LU both cap OpenBLAS's one pool.
  // ctest runs with one thread (OMP_NUM_THREADS=1): the pool is raised to 4 first, so that every
  // cap below changes it (or keeps it where a wrong restore would change it).
  if (blas_threads() == 0 || !openblas_set_num_threads) {
    const BlasThreadCap cap(1);  // not OpenBLAS: nothing to cap, and the cap changes nothing
    CHECK(blas_threads() == 0);
    return;
  }
  const int original = blas_threads();
  openblas_set_num_threads(4);
  const int before = blas_threads();
  REQUIRE(before >= 2);  // OpenBLAS may hold it to the cores it found: 2 here
  {
    std::optional<BlasThreadCap> budget(std::in_place, std::max(1, before - 1));
    CHECK(blas_threads() == std::max(1, before - 1));
    {
      const BlasThreadCap serial(1);
      CHECK(blas_threads() == 1);
      const BlasThreadCap wide(before + 8);  // a cap above the pool never grows it
      CHECK(blas_threads() == 1);
      budget.reset();  // the budget ends first (overlapping, not nested): the H-LU's cap holds
      CHECK(blas_threads() == 1);
    }
    CHECK(blas_threads() == before);
    const BlasThreadCap none(0);
    CHECK(blas_threads() == before);
  }
  CHECK(blas_threads() == before);
  openblas_set_num_threads(original);
}

TEST_CASE("background work gets cores - 1 threads while a loop runs", "[haptics][continuity]") {
  CHECK(background_thread_count(2) == 1);
  CHECK(background_thread_count(1) == 1);
  CHECK(background_thread_count(16) == 15);
#ifdef _OPENMP
  const int before = omp_get_max_threads();
  omp_set_num_threads(4);
  {
    const BackgroundThreadBudget budget;
    CHECK(budget.threads() == background_thread_count());
    CHECK(omp_get_max_threads() == std::min(4, budget.threads()));
    BackgroundTask<int> task;  // a worker thread: at most the budget, whatever its own default
    task.start([] { return omp_get_max_threads(); }, budget.threads());
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!task.ready() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    CHECK(task.take() <= budget.threads());
    CHECK(!task.busy());
  }
  CHECK(omp_get_max_threads() == 4);  // restored
  const BackgroundThreadBudget off(false);
  CHECK(off.threads() == 0);
  CHECK(omp_get_max_threads() == 4);
  omp_set_num_threads(before);
#endif
  BackgroundTask<int> failing;
  failing.start([]() -> int { throw ContactError("refused"); }, 1);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!failing.ready() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  CHECK_THROWS_AS(failing.take(), ContactError);  // the step's error reaches the simulation side
}

// A stalled scheduler (a 5 ms gap in a 1 kHz loop on a shared machine) moves a scripted press five
// periods in one tick; the felt figures count changes per period, so the stall does not read as a
// click, while a real step of the force on a punctual tick still reads at its full size.
TEST_CASE("the felt tick change is per loop period: a late tick is not a click, a step still is", "[haptics][continuity]") {
  const double period = 1e-3;
  auto ramp = [&](FeltForceRecorder& r, double stall_at, double stall_periods, double step_at) {
    double t = 0.0;
    while (t < 1.0 + 1e-12) {
      double f = t;  // 1 N/s: 0..1 N
      if (t >= step_at) f *= 1.1;
      r.add(0, t, Vec3(0, 0, f), Vec3(0, 0, f));
      t += (std::abs(t - stall_at) < 0.5 * period) ? stall_periods * period : period;
    }
  };
  // Independently: over ticks above 10 % of the 1 N peak, a steady ramp changes most at its first
  // pair, 1 ms / 101 ms (~0.99 %); the stall at 0.2 s would otherwise read 5 ms / 205 ms (~2.4 %).
  const double steady = 0.001 / 0.101;
  FeltForceRecorder per_period(1, 3.3, period), as_is(1, 3.3);
  ramp(per_period, 0.2, 5.0, 2.0);
  ramp(as_is, 0.2, 5.0, 2.0);
  CHECK(per_period.result().max_tick_change_fraction == Approx(steady).epsilon(0.02));
  CHECK(as_is.result().max_tick_change_fraction == Approx(0.005 / 0.205).epsilon(0.02));
  CHECK(as_is.result().max_tick_change_time == Approx(0.205).margin(1e-9));
  // A 10 % step at 0.5 s on a punctual tick: (0.5005 * 1.1 - 0.4995) / 0.5505, about 9.3 %.
  FeltForceRecorder stepped(1, 3.3, period);
  ramp(stepped, -1.0, 1.0, 0.5);
  const FeltForce felt = stepped.result();
  CHECK(felt.max_tick_change_fraction > 0.09);
  CHECK(felt.max_tick_change_time == Approx(0.5).margin(1.5 * period));
}
