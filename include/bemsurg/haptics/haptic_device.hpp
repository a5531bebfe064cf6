// bemsurg/haptics/haptic_device.hpp: the one abstract haptic device the simulation talks to
// (Wang et al. 2007 §6 used a PHANToM at about 1 kHz; docs/design.md §1 "haptics" module), and a
// NullDevice so every program runs without hardware (CHAI3D's habit). A missing device is
// reported with the reason, never as a silent "zero devices".
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

namespace bemsurg::haptics {

/// What the device reports each haptic tick.
struct DeviceState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();   // tool tip, metres, simulation frame
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();  // tool axis (unit)
  bool button = false;                                   // e.g. close the pinch / start a cut
};

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  /// Human-readable name ("null device", a model name).
  virtual std::string name() const = 0;
  /// Whether the device is usable; when not, `why()` says what is missing.
  virtual bool available() const = 0;
  virtual std::string why() const = 0;
  /// Called from the haptic thread: must not block or allocate.
  virtual DeviceState read() = 0;
  virtual void write_force(const Eigen::Vector3d& force) = 0;
  /// The largest force the device can render, newtons (feeds ForceLimiter).
  virtual double max_force() const = 0;
};

/// A device with no hardware: the pose is set by the program (scripted experiments, tests, the
/// viewer's mouse) and the last force written is kept for inspection.
class NullDevice : public HapticDevice {
 public:
  explicit NullDevice(double max_force = 10.0) : max_force_(max_force) {}
  std::string name() const override { return "null device"; }
  bool available() const override { return true; }
  std::string why() const override { return "no hardware: the pose is scripted"; }
  DeviceState read() override { return state_; }
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
