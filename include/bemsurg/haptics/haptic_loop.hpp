// bemsurg/haptics/haptic_loop.hpp: the haptic loop — its own thread at a fixed rate (1 kHz default,
// up to 10 kHz) that reads the devices, turns button edges into events for the simulation side,
// computes each tool's force from the contact model and writes it back, safely (docs/haptics.md;
// docs/design.md §9; Wang et al. 2007 §6 ran a PHANToM at about 1 kHz).
//
// The haptic thread never locks, allocates, throws or waits on the other threads:
//   * contact models (an engaged ToolContactSolver on immutable mesh/table snapshots) are built off
//     the thread and offered through a one-slot atomic mailbox; the loop takes a new one between
//     ticks, and hands the old one back through a ring for the simulation side to free. A cut or a
//     re-engagement is therefore seen whole or not at all;
//   * samples (pose, force, contact elements per channel) leave through a bounded ring (the trace)
//     and a triple buffer (the newest, for graphics); button edges through an event ring.
// A new model does not replace the old one at once: both are stepped at the device's pose and the
// force is blended from the old model's to the new one's over blend_s (model_crossfade.hpp), so a
// cut step, a parameter change or an engagement never steps the force.
// Safety, in this order each tick: a failed contact step keeps the previous force; a non-finite
// force is replaced by the last good one (NaN guard); a watchdog gain ramps to zero (and back) when
// the simulation side's heartbeat (it is alive, busy or not) is stale, the loop overran `overrun_limit` ticks in a row, or a
// fault was caught; ForceLimiter bounds the magnitude (3.3 N default) and its rate (N/s). The
// devices get zero force on start, on stop, when disconnected and after an exception.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "bemsurg/haptics/force_limiter.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/haptics/loop_statistics.hpp"
#include "bemsurg/haptics/model_crossfade.hpp"
#include "bemsurg/haptics/spsc_ring.hpp"
#include "bemsurg/haptics/triple_buffer.hpp"
#include "bemsurg/presolution/contact_tools.hpp"

namespace bemsurg::haptics {

constexpr int kMaxChannels = 4;

/// What the haptic thread computes forces from. Built and engaged off the haptic thread, then
/// owned by the loop from offer() until it comes back from take_retired().
/// \ingroup haptics
struct ContactModel {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  std::unique_ptr<ToolContactSolver> solver;
  std::uint64_t version = 0;  // increasing; samples carry the version they were computed with
  /// Per device channel: the solver tool it drives, or -1 (no contact, zero force).
  std::array<int, kMaxChannels> tool_of_channel{{-1, -1, -1, -1}};
  /// Per channel: the device orientation at engagement (a plate turns by the change from it).
  std::array<Eigen::Quaterniond, kMaxChannels> engaged_orientation{
      {Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity()}};
};

/// Settings of a HapticLoop: tick rate, the safety stages (force and force-rate limits, watchdog staleness, overruns and
/// ramp time), the blend between models, ring capacities, and the real-time priority and spin time of the haptic thread.
/// \ingroup haptics
struct HapticLoopOptions {
  double rate_hz = 1000.0;        // 100 .. 10000
  double max_force = 3.3;         // N (a Touch-class desktop device); also capped by each device's own
  double max_force_rate = 300.0;  // N/s: 0.3 N per tick at 1 kHz
  double stale_after_s = 0.25;    // heartbeat older than this: the watchdog ramps the force down
  int overrun_limit = 5;          // this many overruns in a row: the watchdog ramps the force down
  double ramp_s = 0.05;           // watchdog ramp time from full force to zero (and back)
  /// A new model's force replaces the old one's linearly over this time (0: switch at once);
  /// a model offered during a blend waits until it ends (docs/haptics.md, "Model swaps").
  double blend_s = kDefaultModelBlendSeconds;
  int max_active_set_iterations = 20;
  std::size_t trace_capacity = 1 << 15;  // samples the trace ring holds before the reader drains it
  std::size_t event_capacity = 256;
  Index publish_capacity = 2048;  // contact elements published per tick for graphics
  /// > 0: ask for SCHED_FIFO at this priority for the haptic thread (what haptic programs do on
  /// Linux; needs CAP_SYS_NICE or an rtprio limit). Refusal is not an error: the loop runs at
  /// normal priority, where other load on the machine can delay its ticks, and
  /// LoopStatistics::realtime_priority says 0. 0: do not ask.
  int realtime_priority = 80;
  /// The thread sleeps until this long before each deadline, then spins: longer is steadier and
  /// costs more CPU (>= the period: it never sleeps, a whole core).
  double spin_us = 150.0;
};

/// Deprecated name (before 0.2), kept one minor version: use HapticLoopOptions.

using HapticLoopSettings [[deprecated("renamed to HapticLoopOptions in bemsurg 0.2")]] = HapticLoopOptions;

/// One device channel in one tick: the pose in the model frame, the contact model's force and the force sent after the
/// safety stages, buttons, contact elements and the contact step's status.
/// \ingroup haptics
struct ChannelSample {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // model frame
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  // What the newest contact model gave (model frame); during a swap the force sent is blended
  // from the old model's to this (TickSample::blend_weight).
  Eigen::Vector3d model_force = Eigen::Vector3d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // what was sent, after the safety stages
  std::uint32_t buttons = 0;
  int contact_elements = 0;
  ContactStatus status = ContactStatus::Ok;
  bool connected = true;
};

/// What one tick of the haptic loop did, per channel, with the session time, the model version and the watchdog gain:
/// the entries of the trace (pop_sample) and the newest sample for graphics (latest).
/// \ingroup haptics
struct TickSample {
  std::uint64_t tick = 0;
  double time = 0.0;  // session seconds
  std::uint64_t model_version = 0;
  double watchdog_gain = 1.0;
  double blend_weight = 1.0;  // the newest model's share of the force sent (< 1 while a swap blends)
  // Microseconds from the tick's start to its trace entry: the force computation and the safety
  // stages, the per-tick value behind LoopStatistics' force_us (which also counts the push itself).
  double compute_us = 0.0;
  std::array<ChannelSample, kMaxChannels> channel{};
};

/// The contact state the graphics side needs to draw the deformed body: the extra tractions on the
/// contact elements (CapacitanceContact::contact_tractions) and the model they belong to. The
/// field is then GreensTable::displacement_field(elements, tractions, count, u) on that model's
/// read-only table, with the reader's own buffers.
/// \ingroup haptics
struct PublishedContact {
  std::uint64_t model_version = 0;
  double time = 0.0;
  Index count = 0;
  bool overflow = false;  // more contact elements than publish_capacity: count is 0
  std::vector<Index> elements;
  std::vector<double> tractions;  // 3 per element
};

/// A button edge on a device channel (press or release), with the pose in the model frame at the edge: what the haptic
/// thread hands the simulation side (pop_event).
/// \ingroup haptics
struct ButtonEvent {
  double time = 0.0;
  int channel = 0;
  int button = 0;
  bool down = false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // model frame, at the edge
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// The haptic loop: its own thread at a fixed rate that reads the devices, computes each tool's force from the contact model
/// and writes it back through the safety stages, never locking, allocating, throwing or waiting (docs/haptics.md).
/// \ingroup haptics
class HapticLoop {
 public:
  /// `devices[c]` drives channel c (at most kMaxChannels; the loop does not own them and they
  /// must outlive it); `workspaces[c]` maps its frame into the model's (default: identity).
  /// Throws InvalidArgumentError for bad settings or too many / null devices.
  HapticLoop(const HapticLoopOptions& settings, std::vector<HapticDevice*> devices, std::vector<Workspace> workspaces = {});
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  // ---- the thread --------------------------------------------------------------------------
  /// Sends zero force, then runs tick() at the fixed rate on a new thread (sleeping until shortly
  /// before each deadline, then spinning). Session time starts at 0.
  void start();
  /// Stops and joins the thread, then sends zero force to every device. Idempotent.
  void stop();
  bool running() const { return running_.load(std::memory_order_acquire); }

  /// One tick at session time `now` (seconds). The thread calls it; tests and virtual-clock runs
  /// call it directly (then not while the thread runs). `late`: this tick overran.
  void tick(double now, bool late = false) noexcept;

  // ---- simulation side (one thread) ---------------------------------------------------------
  /// Offers a model; the loop takes it before a tick when no blend is running (at most blend_s
  /// later) and blends from the old model's force to its. False (the model stays with the
  /// caller) while an earlier offer has not been taken yet.
  bool offer(std::unique_ptr<ContactModel>& model);
  /// Whether an offered model is still waiting to be taken.
  bool offer_pending() const noexcept { return offered_.load(std::memory_order_acquire) != nullptr; }
  /// Session time of the latest tick (seconds).
  double time() const noexcept { return now_.load(std::memory_order_acquire); }
  /// A model the loop no longer uses (to be freed here, off the haptic thread), or null.
  std::unique_ptr<ContactModel> take_retired();
  /// "The simulation side is alive": the watchdog ramps the force down when this is not called for
  /// stale_after_s of session time. Beat it while long work (a cut step) runs elsewhere: the loop
  /// renders the old model meanwhile; stop beating when the simulation side is hung or gone.
  void heartbeat() noexcept;
  /// The next trace sample (one per tick, in order) / button event; false when none is waiting.
  bool pop_sample(TickSample& out) noexcept { return trace_.pop(out); }
  bool pop_event(ButtonEvent& out) noexcept { return events_.pop(out); }
  /// The newest sample, for graphics (false when none is newer than the last call's).
  bool latest(TickSample& out) noexcept;
  /// The newest published contact (graphics side, one reader thread), or null when nothing newer
  /// was published since the last call. Valid until the next call.
  const PublishedContact* latest_contact() noexcept { return contact_out_.acquire() ? &contact_out_.front() : nullptr; }
  /// Version of the model the loop renders now (0: none).
  std::uint64_t model_version() const noexcept { return rendered_version_.load(std::memory_order_acquire); }
  /// Statistics so far (complete after stop(); while running, from the simulation side only
  /// the atomic counters are safe, so call it after stop()).
  LoopStatistics statistics() const;
  const HapticLoopOptions& settings() const { return settings_; }
  int channels() const { return static_cast<int>(devices_.size()); }

 private:
  void run();
  void zero_all() noexcept;
  // The steps of tick(), in order; they may throw only where a device or the model does. Inline
  // (defined in haptic_loop.cpp, used only by tick()) so that the compiler folds them back into
  // the tick: the hot path costs what it cost as one function.
  inline void take_offered_model(double now);
  inline void retire_blended_model();
  inline void update_watchdog(double now, double dt, bool late);
  inline void read_channel(int channel, double now, ChannelSample& cs);
  inline bool pose_tool(ContactModel* model, int channel, const DeviceState& s);
  inline void push_button_edges(int channel, double now, const DeviceState& s);
  inline ContactStatus step_contact(ContactModel* model);
  inline Eigen::Vector3d model_force(const ContactModel* model, int channel, ContactStatus step_status, int* elements) const;
  inline void publish_contact(double now, const ToolContactSolver* solver);
  inline void write_channel_force(int channel, ContactStatus step_status, ContactStatus old_status, double weight, double dt,
                                  ChannelSample& cs);
  inline void record_tick(TickSample& sample, double now, double dt, bool late, std::chrono::steady_clock::time_point t_start) noexcept;

  HapticLoopOptions settings_;
  std::vector<HapticDevice*> devices_;
  std::vector<Workspace> workspaces_;
  std::vector<ForceLimiter> limiters_;
  std::array<Eigen::Vector3d, kMaxChannels> held_{};  // last good model force per channel
  std::array<std::uint32_t, kMaxChannels> last_buttons_{};
  ContactModel* current_ = nullptr;
  ContactModel* previous_ = nullptr;  // the model blended out, until the blend ends
  ModelCrossfade blend_;
  std::atomic<ContactModel*> offered_{nullptr};
  SpscRing<ContactModel*> retired_{8};
  SpscRing<TickSample> trace_;
  SpscRing<ButtonEvent> events_;
  TripleBuffer<TickSample> newest_;
  TripleBuffer<PublishedContact> contact_out_;
  std::atomic<std::uint64_t> rendered_version_{0};
  std::atomic<double> heartbeat_time_{0.0};
  std::atomic<double> now_{0.0};
  std::atomic<bool> running_{false};
  std::thread thread_;
  // Haptic-thread state (read by statistics() after stop()).
  bool first_tick_ = true;
  double last_time_ = 0.0;
  double gain_ = 1.0;
  int overruns_in_a_row_ = 0;
  bool fault_ = false;
  std::uint64_t tick_count_ = 0;
  double first_time_ = 0.0;
  MicrosecondHistogram jitter_, force_time_;
  LoopStatistics counters_;
};

}  // namespace bemsurg::haptics
