// bemsurg/haptics/recording_device.hpp: wraps any device and records what it reported and what it
// was sent, tick by tick, into memory reserved up front (the haptic thread never allocates); after
// the session the record is written as CSV, which ScriptedDevice::read_csv plays back (replay).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bemsurg/haptics/haptic_device.hpp"

namespace bemsurg::haptics {

/// Wraps any device and records what it reported and what it was sent, tick by tick, into memory reserved up front; after
/// the session the record is written as CSV, which ScriptedDevice::read_csv plays back.
/// \ingroup haptics
class RecordingDevice : public HapticDevice {
 public:
  /// One recorded tick: the session time, the state the device reported and the force written after that read.
  struct Sample {
    double time = 0.0;
    DeviceState state;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();  // the force written after this read
  };
  /// Records up to `capacity` ticks; later ones are counted in overflow() and not kept.
  RecordingDevice(std::unique_ptr<HapticDevice> inner, std::size_t capacity);

  std::string name() const override { return "recording " + inner_->name(); }
  bool available() const override { return inner_->available(); }
  std::string why() const override { return inner_->why(); }
  DeviceState read(double session_time) override;
  void write_force(const Eigen::Vector3d& force) override;
  double max_force() const override { return inner_->max_force(); }
  std::uint64_t dropped_packets() const override { return inner_->dropped_packets(); }

  /// After the loop has stopped: the record, and the CSV of it
  /// (`time,x,y,z,dx,dy,dz,buttons,connected,fx,fy,fz`). Throws IoError when it cannot write.
  const std::vector<Sample>& samples() const { return samples_; }
  std::size_t overflow() const { return overflow_; }
  void write_csv(const std::string& path) const;
  HapticDevice& inner() { return *inner_; }

 private:
  std::unique_ptr<HapticDevice> inner_;
  std::vector<Sample> samples_;
  std::size_t capacity_;
  std::size_t overflow_ = 0;
};

}  // namespace bemsurg::haptics
