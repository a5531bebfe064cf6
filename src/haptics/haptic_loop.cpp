// Implementation of bemsurg/haptics/haptic_loop.hpp: the fixed-rate haptic thread, its safety
// stages and its statistics (docs/haptics.md).
#include "bemsurg/haptics/haptic_loop.hpp"

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <cmath>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::haptics {

namespace {
PublishedContact contact_prototype(Index capacity) {
  PublishedContact p;
  p.elements.assign(static_cast<std::size_t>(std::max<Index>(capacity, 1)), 0);
  p.tractions.assign(3 * p.elements.size(), 0.0);
  return p;
}
}  // namespace

HapticLoop::HapticLoop(const HapticLoopOptions& settings, std::vector<HapticDevice*> devices, std::vector<Workspace> workspaces)
    : settings_(settings),
      devices_(std::move(devices)),
      workspaces_(std::move(workspaces)),
      trace_(settings.trace_capacity),
      events_(settings.event_capacity),
      contact_out_(contact_prototype(settings.publish_capacity)) {
  if (!(settings.rate_hz >= 100.0 && settings.rate_hz <= 10000.0))
    throw InvalidArgumentError("HapticLoop: rate_hz must lie in [100, 10000], got " + number_text(settings.rate_hz));
  if (!(settings.stale_after_s > 0.0) || !(settings.ramp_s > 0.0) || settings.overrun_limit < 1 || !(settings.spin_us >= 0.0))
    throw InvalidArgumentError("HapticLoop: stale_after_s and ramp_s must be positive, spin_us non-negative and overrun_limit at least 1");
  if (!(settings.blend_s >= 0.0 && settings.blend_s <= 1.0))
    throw InvalidArgumentError("HapticLoop: blend_s must lie in [0, 1] s, got " + number_text(settings.blend_s));
  if (settings.realtime_priority < 0 || settings.realtime_priority > 99)
    throw InvalidArgumentError("HapticLoop: realtime_priority must lie in [0, 99], got " + std::to_string(settings.realtime_priority));
  blend_.set_duration(settings.blend_s);
  if (devices_.empty() || devices_.size() > static_cast<std::size_t>(kMaxChannels))
    throw InvalidArgumentError("HapticLoop: between 1 and " + std::to_string(kMaxChannels) + " devices, got " +
                               std::to_string(devices_.size()));
  for (std::size_t c = 0; c < devices_.size(); ++c)
    if (!devices_[c]) throw InvalidArgumentError("HapticLoop: device " + std::to_string(c) + " is null");
  if (workspaces_.empty()) workspaces_.assign(devices_.size(), Workspace{});
  if (workspaces_.size() != devices_.size()) throw InvalidArgumentError("HapticLoop: one workspace per device, or none");
  for (HapticDevice* d : devices_)
    limiters_.emplace_back(std::min(settings.max_force, d->max_force()), settings.max_force_rate);  // throws when <= 0
  held_.fill(Eigen::Vector3d::Zero());
  last_buttons_.fill(0);
  counters_.rate_hz = settings.rate_hz;
}

HapticLoop::~HapticLoop() {
  stop();
  delete offered_.exchange(nullptr);
  ContactModel* m = nullptr;
  while (retired_.pop(m)) delete m;
  delete previous_;
  delete current_;
}

void HapticLoop::zero_all() noexcept {
  for (std::size_t c = 0; c < devices_.size(); ++c) {
    devices_[c]->write_force(Eigen::Vector3d::Zero());
    limiters_[c].reset();
  }
}

bool HapticLoop::offer(std::unique_ptr<ContactModel>& model) {
  if (!model) return false;
  ContactModel* expected = nullptr;
  if (!offered_.compare_exchange_strong(expected, model.get(), std::memory_order_acq_rel)) return false;
  model.release();
  return true;
}

std::unique_ptr<ContactModel> HapticLoop::take_retired() {
  ContactModel* m = nullptr;
  return std::unique_ptr<ContactModel>(retired_.pop(m) ? m : nullptr);
}

void HapticLoop::heartbeat() noexcept { heartbeat_time_.store(now_.load(std::memory_order_relaxed), std::memory_order_release); }

bool HapticLoop::latest(TickSample& out) noexcept {
  if (!newest_.acquire()) return false;
  out = newest_.front();
  return true;
}

// The steps of one tick, in order (see tick()). None allocates: the haptic thread never does.

void HapticLoop::take_offered_model(double now) {
  // A new model, between ticks, when no blend is running: the current one is blended out over
  // blend_s (or, with blend_s = 0 or no model yet, goes back to the simulation side at once, to
  // be freed there). Taken only when there is room to hand the old ones back.
  if (previous_ || offered_.load(std::memory_order_acquire) == nullptr || retired_.full()) return;
  ContactModel* next = offered_.exchange(nullptr, std::memory_order_acq_rel);
  if (current_ && settings_.blend_s > 0.0) {
    previous_ = current_;
    blend_.start(now);
  } else if (current_) {
    retired_.push(current_);
  }
  current_ = next;
  rendered_version_.store(current_->version, std::memory_order_release);
  ++counters_.model_swaps;
}

void HapticLoop::retire_blended_model() {
  // The blend is over: the old model goes back (it stays until the ring has room).
  if (previous_ && !blend_.active() && retired_.push(previous_)) previous_ = nullptr;
}

void HapticLoop::update_watchdog(double now, double dt, bool late) {
  // Stale simulation state, repeated overruns or a fault ramp the gain to zero (and back).
  const int in_a_row = late ? overruns_in_a_row_ + 1 : overruns_in_a_row_;
  const bool stale = now - heartbeat_time_.load(std::memory_order_acquire) > settings_.stale_after_s;
  const bool unhealthy = stale || in_a_row >= settings_.overrun_limit || fault_;
  const double ramp = std::max(0.0, dt) / settings_.ramp_s;
  gain_ = unhealthy ? std::max(0.0, gain_ - ramp) : std::min(1.0, gain_ + ramp);
  if (unhealthy) ++counters_.watchdog_ticks;
}

void HapticLoop::push_button_edges(int channel, double now, const DeviceState& s) {
  const auto cu = static_cast<std::size_t>(channel);
  const std::uint32_t changed = s.buttons ^ last_buttons_[cu];
  for (int b = 0; changed >> b; ++b)
    if ((changed >> b) & 1U) {
      ButtonEvent e;
      e.time = now;
      e.channel = channel;
      e.button = b;
      e.down = (s.buttons >> b) & 1U;
      e.position = s.position;
      e.direction = s.direction;
      e.orientation = s.orientation;
      events_.push(e);  // a full event ring drops the edge; the simulation side sees the buttons in the trace
    }
  last_buttons_[cu] = s.buttons;
}

bool HapticLoop::pose_tool(ContactModel* model, int channel, const DeviceState& s) {
  // The tool the channel drives in `model` follows the device: translation from its engagement
  // origin, and a plate turns by the device's rotation since engagement. False: a non-finite pose.
  const auto cu = static_cast<std::size_t>(channel);
  ToolContactSolver* solver = model ? model->solver.get() : nullptr;
  const int tool = model ? model->tool_of_channel[cu] : -1;
  if (!solver || tool < 0 || !s.connected || !solver->engaged(tool)) return true;
  bool ok = solver->try_set_translation(tool, s.position - solver->origin(tool));
  if (solver->spec(tool).shape == ToolShape::Plate) {
    const Eigen::AngleAxisd turn(s.orientation * model->engaged_orientation[cu].conjugate());
    ok = solver->try_set_rotation(tool, turn.angle() * turn.axis()) && ok;
  }
  return ok;
}

void HapticLoop::read_channel(int channel, double now, ChannelSample& cs) {
  // Device -> pose (model frame) -> the tool it drives in the contact model (and in the model
  // being blended out).
  const auto cu = static_cast<std::size_t>(channel);
  const DeviceState s = workspaces_[cu].to_model(devices_[cu]->read(now));
  cs.position = s.position;
  cs.direction = s.direction;
  cs.buttons = s.buttons;
  cs.connected = s.connected;
  cs.status = ContactStatus::Ok;
  push_button_edges(channel, now, s);
  const bool ok = pose_tool(current_, channel, s);
  if (previous_) pose_tool(previous_, channel, s);
  if (!ok) cs.status = ContactStatus::NonFinitePose;
}

ContactStatus HapticLoop::step_contact(ContactModel* model) {
  ToolContactSolver* solver = model ? model->solver.get() : nullptr;
  if (!solver) return ContactStatus::Ok;
  ContactUpdateResult report;
  const ContactStatus status = solver->step(report, settings_.max_active_set_iterations);
  if (status == ContactStatus::CapacityExceeded || status == ContactStatus::Singular) ++counters_.failed_steps;
  return status;
}

void HapticLoop::publish_contact(double now, const ToolContactSolver* solver) {
  // For graphics: the field is computed there from the read-only table.
  PublishedContact& pc = contact_out_.back();
  pc.model_version = current_ ? current_->version : 0;
  pc.time = now;
  pc.count = 0;
  pc.overflow = false;
  if (solver) {
    if (solver->contact().num_elements() <= static_cast<Index>(pc.elements.size()))
      pc.count = solver->contact().contact_tractions(pc.elements.data(), pc.tractions.data());
    else
      pc.overflow = true;
  }
  contact_out_.publish();
}

Eigen::Vector3d HapticLoop::model_force(const ContactModel* model, int channel, ContactStatus step_status, int* elements) const {
  // The force of the tool the channel drives in `model`; zero when none is engaged; the last good
  // force when the set change failed.
  const auto cu = static_cast<std::size_t>(channel);
  const ToolContactSolver* solver = model ? model->solver.get() : nullptr;
  const int tool = model ? model->tool_of_channel[cu] : -1;
  if (!solver || tool < 0 || !solver->engaged(tool)) return Eigen::Vector3d::Zero();
  if (step_status != ContactStatus::Ok && step_status != ContactStatus::Unsettled) return held_[cu];
  if (elements) *elements = static_cast<int>(solver->contact_elements(tool));
  return solver->force(tool);
}

void HapticLoop::write_channel_force(int channel, ContactStatus step_status, ContactStatus old_status, double weight, double dt,
                                     ChannelSample& cs) {
  // The newest model's force (held when its step failed, NaN guard), blended from the old model's
  // during a swap, through the watchdog gain and the limiter, out to the device.
  const auto cu = static_cast<std::size_t>(channel);
  cs.contact_elements = 0;
  if (!cs.connected) {
    // Device lost: zero at once (no ramp: there may be no hand on it), and ramp up from zero later.
    devices_[cu]->write_force(Eigen::Vector3d::Zero());
    limiters_[cu].reset();
    held_[cu].setZero();
    cs.model_force.setZero();
    cs.force.setZero();
    return;
  }
  const int tool = current_ ? current_->tool_of_channel[cu] : -1;
  if (cs.status == ContactStatus::Ok && tool >= 0 && current_->solver && current_->solver->engaged(tool)) cs.status = step_status;
  Eigen::Vector3d newest = model_force(current_, channel, step_status, &cs.contact_elements);
  if (!newest.allFinite()) {
    ++counters_.nan_guards;
    newest = held_[cu];
  }
  held_[cu] = newest;
  cs.model_force = newest;
  Eigen::Vector3d requested = newest;
  if (previous_ && weight < 1.0) {
    Eigen::Vector3d old = model_force(previous_, channel, old_status, nullptr);
    if (!old.allFinite()) old = newest;
    requested = ModelCrossfade::mix(old, newest, weight);
  }
  const Eigen::Vector3d wanted = gain_ * requested;
  const Eigen::Vector3d out = limiters_[cu](wanted, dt);
  if ((out - wanted).norm() > 1e-12 * (1.0 + wanted.norm())) ++counters_.clamped_ticks;
  cs.force = out;
  devices_[cu]->write_force(workspaces_[cu].to_device_force(out));
}

void HapticLoop::record_tick(TickSample& sample, double now, double dt, bool late, std::chrono::steady_clock::time_point t_start) noexcept {
  const double nominal = 1.0 / settings_.rate_hz;
  sample.tick = tick_count_;
  sample.time = now;
  sample.model_version = current_ ? current_->version : 0;
  sample.watchdog_gain = gain_;
  sample.compute_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t_start).count();
  if (!trace_.push(sample)) ++counters_.trace_dropped;
  newest_.publish();
  const double compute_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t_start).count();
  force_time_.add(compute_us);
  if (!first_tick_) jitter_.add(std::abs(dt - nominal) * 1e6);
  // An overrun: the tick started a whole period late, or took longer than its period.
  const bool overran = late || compute_us > nominal * 1e6;
  overruns_in_a_row_ = overran ? overruns_in_a_row_ + 1 : 0;
  if (overran) ++counters_.overruns;
  first_tick_ = false;
  last_time_ = now;
  ++tick_count_;
}

void HapticLoop::tick(double now, bool late) noexcept {
  const auto t_start = std::chrono::steady_clock::now();
  const double dt = first_tick_ ? 1.0 / settings_.rate_hz : now - last_time_;
  if (first_tick_) {
    first_time_ = now;
    heartbeat_time_.store(now, std::memory_order_relaxed);
  }
  now_.store(now, std::memory_order_relaxed);
  TickSample& sample = newest_.back();
  try {
    take_offered_model(now);  // 1. a new model, between ticks (the old one blended out)
    const double weight = blend_.weight(now);
    sample.blend_weight = previous_ ? weight : 1.0;
    update_watchdog(now, dt, late);  // 2. the gain the forces are scaled by
    // 3. Devices -> poses (model frame) -> the contact models, published for graphics.
    const int n = static_cast<int>(devices_.size());
    for (int c = 0; c < n; ++c) read_channel(c, now, sample.channel[static_cast<std::size_t>(c)]);
    const ContactStatus step_status = step_contact(current_);
    const ContactStatus old_status = previous_ && weight < 1.0 ? step_contact(previous_) : ContactStatus::Ok;
    publish_contact(now, current_ ? current_->solver.get() : nullptr);
    // 4. Forces through the safety stages, out to the devices.
    for (int c = 0; c < n; ++c) write_channel_force(c, step_status, old_status, weight, dt, sample.channel[static_cast<std::size_t>(c)]);
    retire_blended_model();
  } catch (...) {
    // Nothing above should throw; if a device or the model does, the hand gets zero force and
    // the watchdog keeps it there (the fault is sticky: a session that faulted must be restarted).
    ++counters_.faults;
    fault_ = true;
    gain_ = 0.0;
    zero_all();
  }
  record_tick(sample, now, dt, late, t_start);  // 5. trace, newest sample, timing statistics
}

void HapticLoop::start() {
  if (running_.load()) return;
  zero_all();
  first_tick_ = true;
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] { run(); });
}

void HapticLoop::run() {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / settings_.rate_hz));
  const auto spin = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::micro>(settings_.spin_us));
  if (settings_.realtime_priority > 0) {
    sched_param p{};
    p.sched_priority = settings_.realtime_priority;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0) counters_.realtime_priority = settings_.realtime_priority;
  }
  const auto t0 = Clock::now();
  auto next = t0;
  while (running_.load(std::memory_order_acquire)) {
    // Sleep until shortly before the deadline, then spin: sleeping alone wakes up to ~60 us late,
    // spinning alone would take a whole core from the simulation side.
    if (next - Clock::now() > spin) std::this_thread::sleep_until(next - spin);
    while (Clock::now() < next) {}
    const auto now = Clock::now();
    const bool late = now - next >= period;  // this tick's slot was missed entirely
    tick(std::chrono::duration<double>(now - t0).count(), late);
    next += period;
    if (Clock::now() > next + period) next = Clock::now();  // do not race to catch up missed ticks
  }
  zero_all();
}

void HapticLoop::stop() {
  if (!running_.exchange(false)) {
    if (!thread_.joinable()) return;
  }
  if (thread_.joinable()) thread_.join();
  zero_all();
}

LoopStatistics HapticLoop::statistics() const {
  LoopStatistics s = counters_;
  s.ticks = tick_count_;
  if (tick_count_ > 1 && last_time_ > first_time_) s.achieved_rate_hz = double(tick_count_ - 1) / (last_time_ - first_time_);
  s.jitter_us = percentiles_of(jitter_);
  s.force_us = percentiles_of(force_time_);
  s.dropped_packets = 0;
  for (HapticDevice* d : devices_) s.dropped_packets += d->dropped_packets();
  return s;
}

}  // namespace bemsurg::haptics
