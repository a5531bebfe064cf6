// examples/viewer/tool_stepper.hpp: one haptic tick of the viewer: read each tool's device
// (the mouse, a pinned pose or a script: all bemsurg::haptics::HapticDevice), engage or release on
// the button, move the engaged tools, solve the exact multi-tool contact (ToolContactSolver on the
// compliance table, docs/design.md §6), limit the force and write it back to the device, and fill a
// snapshot (contact elements and tractions, forces, tool poses) that the graphics thread turns into
// the deformed surface (docs/design.md §9: the graphics thread computes the field from the
// read-only table, never from the solver the haptic thread is using).
//
// The mouse is a device like any other (MouseDevice): the GUI writes its pose through a triple
// buffer, the haptic thread reads it. Engagement (a ray cast and a contact-set change) happens on
// the tick where the button goes down, as ToolContactSolver does it today.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "bemsurg/haptics/force_limiter.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/haptics/model_crossfade.hpp"
#include "bemsurg/haptics/triple_buffer.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "model_worker.hpp"
#include "tool_kind.hpp"

namespace bemsurg::viewer {

constexpr int kMaxTools = 2;

/// The mouse as a haptic device: the GUI thread sets the pose, the haptic thread reads it;
/// the last force written is kept for display.
class MouseDevice : public haptics::HapticDevice {
 public:
  explicit MouseDevice(std::string name) : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  bool available() const override { return true; }
  std::string why() const override { return "the mouse: no force is rendered to the hand"; }
  haptics::DeviceState read(double) noexcept override {
    pose_.acquire();
    return pose_.front();
  }
  void write_force(const Eigen::Vector3d& f) noexcept override {
    for (int k = 0; k < 3; ++k) force_[k].store(f(k), std::memory_order_relaxed);
  }
  double max_force() const override { return 1e9; }
  /// GUI thread.
  void set_state(const haptics::DeviceState& s) {
    pose_.back() = s;
    pose_.publish();
  }
  Eigen::Vector3d last_force() const {
    return {force_[0].load(std::memory_order_relaxed), force_[1].load(std::memory_order_relaxed),
            force_[2].load(std::memory_order_relaxed)};
  }

 private:
  std::string name_;
  haptics::TripleBuffer<haptics::DeviceState> pose_;
  std::atomic<double> force_[3] = {0.0, 0.0, 0.0};
};

/// What the GUI chooses for a tool slot.
struct SlotOptions {
  ToolKind kind = ToolKind::Sphere;
  double radius = 0.0;      // sphere/flat radius, pinch jaw; 0 = default from the mesh size
  double plate_size = 0.0;  // plate half-width; 0 = default
  /// Contact of point, sphere and flat: frictionless (normal only) or bonded. Default: sphere and
  /// flat frictionless, point bonded (docs/actions.md).
  bool frictionless = false;
  bool frictionless_given = false;
  /// plate: the outline given by a script (model frame) and its tolerance; empty = a square of
  /// half-width plate_size across the approach direction, centred where the mouse hit.
  std::vector<Eigen::Vector3d> polygon;
  double plate_tolerance = 0.0;
};

struct StepperOptions {
  std::array<SlotOptions, kMaxTools> slots;
  bool haptic_force = true;                             // write the force to the device (off: zero)
  double force_limit = 3.3;                             // newtons (a Touch-class desktop device)
  double force_rate = 300.0;                            // newtons per second: the largest change of the sent force
  double blend_s = haptics::kDefaultModelBlendSeconds;  // old model's force to the new one's after a swap
};

struct SlotSnapshot {
  bool engaged = false;
  bool missed = false;  // the button is down but the tool met nothing
  ToolKind kind = ToolKind::Sphere;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // contact point / sphere centre / disc or plate centre, moved
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  double radius = 0.0;
  double plate_size = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();       // contact force on the tool (newtons), newest model
  Eigen::Vector3d sent_force = Eigen::Vector3d::Zero();  // blended from the old model's after a swap, limited (or zero when off)
  Index contact_elements = 0;
};

struct ContactSnapshot {
  std::uint64_t physics_version = 0;
  std::array<SlotSnapshot, kMaxTools> slots;
  std::vector<Index> elements;    // contact elements (capacity reserved)
  std::vector<double> tractions;  // 3 per contact element: contact traction added to the base state
  Index count = 0;
  double force_seconds = 0.0;       // time of this tick's contact update
  double blend_weight = 1.0;        // the newest model's share of the force sent (< 1 while a swap blends)
  std::array<char, 200> message{};  // last problem ("contact set full", ...) or empty
};

class ToolStepper {
 public:
  ToolStepper();
  /// One tick at session time `time`, `dt` seconds after the previous one. `physics` may be null
  /// or without a table (nothing happens but the snapshot). A cut's provisional state (no table
  /// yet) does not replace the model in use: the tools keep the uncut model until the cut's
  /// tables are ready (Wang et al. 2007 §5.3), and every model swap (a cut, E, nu, gravity) blends
  /// the force sent from the old model's to the new one's over `blend_s` (haptics/model_crossfade.hpp).
  /// A new scene (another model_name) switches at once.
  void tick(const std::shared_ptr<const PhysicsState>& physics, haptics::HapticDevice* const* devices, const StepperOptions& settings,
            double time, double dt, ContactSnapshot& out);

 private:
  struct Slot {
    bool button = false;
    bool engaged = false;
    bool missed = false;
    int tool = -1;
    ToolKind kind = ToolKind::Sphere;
    double radius = 0.0, plate_size = 0.0;
    bool frictionless = false;
    ToolSpec spec;
    Eigen::Vector3d engage_position = Eigen::Vector3d::Zero();
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    haptics::ForceLimiter limiter{3.3, 300.0};
    double limit = 3.3, rate = 300.0;
  };
  bool engage(Slot& s, const SlotOptions& want, const haptics::DeviceState& d, std::string& why);
  /// After a new model (a cut, new parameters): the same tool where it was engaged, at the same
  /// translation, on the new solver.
  bool reengage(Slot& s);
  // The steps of tick(), in order.
  void follow_model(const std::shared_ptr<const PhysicsState>& physics, double time, double blend_s);
  void follow_device(int slot, haptics::HapticDevice* device, const SlotOptions& want, double time);
  void step_contact();
  void send_force(int slot, haptics::HapticDevice* device, const StepperOptions& settings, double dt, double weight, SlotSnapshot& out);

  /// Whether `physics` replaces the model in use now (false: a cut's state without its tables).
  bool takes_over(const std::shared_ptr<const PhysicsState>& physics) const;
  /// During a blend: the old solver's tools follow the devices too; their forces, per slot.
  void step_previous();

  std::shared_ptr<const PhysicsState> physics_;
  std::unique_ptr<ToolContactSolver> solver_;
  // The model blended out after a swap (docs/haptics.md, "Model swaps"), its tool per slot, and
  // the force each slot's tool had in it this tick.
  std::shared_ptr<const PhysicsState> previous_physics_;
  std::unique_ptr<ToolContactSolver> previous_solver_;
  std::array<int, kMaxTools> previous_tool_{{-1, -1}};
  std::array<Eigen::Vector3d, kMaxTools> previous_force_{};
  haptics::ModelCrossfade blend_;
  std::array<Slot, kMaxTools> slots_;
  std::string message_;
};

/// Default tool sizes for a mesh whose elements measure `edge` across.
double default_tool_radius(ToolKind k, double edge);
double default_plate_size(double edge);

}  // namespace bemsurg::viewer
