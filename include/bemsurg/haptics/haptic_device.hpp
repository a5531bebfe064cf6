// bemsurg/haptics/haptic_device.hpp: the one abstract haptic device the simulation talks to
// (Wang et al. 2007 §6 used a PHANToM at about 1 kHz; docs/design.md §1 "haptics" module), the
// workspace mapping from the device's frame into the model's, and a NullDevice so every program
// runs without hardware (CHAI3D's habit). A missing device is reported with the reason, never as a
// silent "zero devices". Other devices: scripted_device.hpp, recording_device.hpp, udp_device.hpp.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>

namespace bemsurg::haptics {

/// What the device reports each haptic tick.
/// \ingroup haptics
struct DeviceState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // tool tip, metres
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // handle orientation
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();            // tool axis (unit)
  std::uint32_t buttons = 0;                                        // bit i: button i is down
  /// False when the device has no fresh state (unplugged, its bridge went silent): the loop sends
  /// zero force to it and its tool does not move.
  bool connected = true;
  bool button(int i = 0) const { return (buttons >> i) & 1U; }
};

/// Device frame -> model frame: x_model = scale * x_device + offset; directions and orientations
/// are not scaled. Forces go back as force_scale * F (1: the model's newtons are the hand's).
/// \ingroup haptics
struct Workspace {
  double scale = 1.0;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  double force_scale = 1.0;
  DeviceState to_model(const DeviceState& s) const noexcept {
    DeviceState m = s;
    m.position = scale * s.position + offset;
    return m;
  }
  Eigen::Vector3d to_device_force(const Eigen::Vector3d& f) const noexcept { return force_scale * f; }
};

/// The one abstract haptic device the simulation talks to: read() gives the pose and buttons, write_force() sends the force,
/// both from the haptic thread without blocking, allocating or throwing; available() and why() say whether it is usable.
/// \ingroup haptics
class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  /// Human-readable name ("null device", a model name).
  virtual std::string name() const = 0;
  /// Whether the device is usable; when not, `why()` says what is missing.
  virtual bool available() const = 0;
  virtual std::string why() const = 0;
  /// Called from the haptic thread with the session time in seconds (scripted devices play their
  /// trajectory at it; hardware ignores it): must not block, allocate or throw.
  virtual DeviceState read(double session_time) = 0;
  /// Called from the haptic thread: must not block, allocate or throw.
  virtual void write_force(const Eigen::Vector3d& force) = 0;
  /// The largest force the device can render, newtons (feeds ForceLimiter).
  virtual double max_force() const = 0;
  /// Input the device refused (network bridges: malformed, late, out-of-order, foreign packets).
  virtual std::uint64_t dropped_packets() const { return 0; }
};

/// A device with no hardware: the pose is set by the program (tests, the viewer's mouse) and the
/// last force written is kept for inspection. set_state and read must be called from one thread.
/// \ingroup haptics
class NullDevice : public HapticDevice {
 public:
  explicit NullDevice(double max_force = 10.0) : max_force_(max_force) {}
  std::string name() const override { return "null device"; }
  bool available() const override { return true; }
  std::string why() const override { return "no hardware: the pose is scripted"; }
  DeviceState read(double) override { return state_; }
  void write_force(const Eigen::Vector3d& force) override {
    last_force_ = force;
    ++writes_;
  }
  double max_force() const override { return max_force_; }

  void set_state(const DeviceState& s) { state_ = s; }
  const Eigen::Vector3d& last_force() const { return last_force_; }
  long writes() const { return writes_; }

 private:
  double max_force_;
  DeviceState state_;
  Eigen::Vector3d last_force_ = Eigen::Vector3d::Zero();
  long writes_ = 0;
};

/// The device a program should use: hardware when a driver is built in (none is, in this build),
/// otherwise a NullDevice; `reason` says why no hardware device was opened.
std::unique_ptr<HapticDevice> open_default_device(std::string& reason);

}  // namespace bemsurg::haptics
