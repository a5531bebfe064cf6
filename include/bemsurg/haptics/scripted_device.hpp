// bemsurg/haptics/scripted_device.hpp: a device whose pose and buttons follow a trajectory — a
// function of time, keyframes (what an action script becomes, docs/actions.md) or a CSV file (what
// RecordingDevice writes, so a recorded session replays through it). Forces written to it are
// kept for inspection. docs/haptics.md describes the CSV columns.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bemsurg/haptics/haptic_device.hpp"

namespace bemsurg::haptics {

/// One point of a trajectory. Between keyframes position and direction are interpolated linearly
/// in time; buttons and `connected` hold the value of the keyframe at or before the time. Two
/// keyframes at the same time make a jump (the later one holds from then on).
/// \ingroup haptics
struct Keyframe {
  double time = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = -Eigen::Vector3d::UnitZ();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::uint32_t buttons = 0;
  bool connected = true;
};

/// A device whose pose and buttons follow a trajectory: a function of time, keyframes or a CSV file (what RecordingDevice
/// writes). Forces written to it are kept for inspection.
/// \ingroup haptics
class ScriptedDevice : public HapticDevice {
 public:
  /// From a function of the session time (it must not allocate, lock or throw).
  explicit ScriptedDevice(std::function<DeviceState(double)> trajectory, std::string name = "scripted device", double max_force = 3.3);
  /// From keyframes (sorted by time; throws InvalidArgumentError when not, or when empty).
  explicit ScriptedDevice(std::vector<Keyframe> keyframes, std::string name = "scripted device", double max_force = 3.3);
  /// From a CSV file with the header `time,x,y,z,dx,dy,dz,buttons` (more columns, e.g. the
  /// recorder's forces, are ignored). Throws IoError naming the file and line at fault.
  static std::vector<Keyframe> read_csv(const std::string& path);

  std::string name() const override { return name_; }
  bool available() const override { return true; }
  std::string why() const override { return "scripted: no hardware"; }
  DeviceState read(double session_time) override;
  void write_force(const Eigen::Vector3d& force) override {
    last_force_ = force;
    ++writes_;
  }
  double max_force() const override { return max_force_; }

  /// The trajectory at `time` (the same as read, without counting).
  DeviceState state_at(double time) const;
  const Eigen::Vector3d& last_force() const { return last_force_; }
  long writes() const { return writes_; }
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }

 private:
  std::function<DeviceState(double)> function_;
  std::vector<Keyframe> keyframes_;
  std::string name_;
  double max_force_;
  Eigen::Vector3d last_force_ = Eigen::Vector3d::Zero();
  long writes_ = 0;
};

}  // namespace bemsurg::haptics
