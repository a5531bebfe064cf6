// bemsurg/haptics/udp_device.hpp: a haptic device on the other side of a loopback UDP socket, so a
// separate program holding a vendor SDK (OpenHaptics, Force Dimension, CHAI3D) drives bemsurg
// without bemsurg linking proprietary code. The packet format (docs/haptics.md, "UDP bridge") is
// versioned, checksummed (CRC-32) and sequenced: packets that are malformed, late, out of order or
// from an unexpected sender are dropped and counted, never acted on.
//
// read() drains the socket without blocking (at most kMaxPacketsPerRead packets per tick) and keeps
// the newest valid pose; write_force() sends one force packet to the sender of the accepted poses.
// Neither allocates. The bridge side's encoder/decoder and a small client are here too, so the
// vendor program (and the tests) speak exactly this format.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>

#include "bemsurg/haptics/haptic_device.hpp"

namespace bemsurg::haptics {

namespace udp {
constexpr std::uint32_t kMagic = 0x50484D42;  // bytes "BMHP"
constexpr std::uint16_t kVersion = 1;
constexpr std::uint16_t kPoseType = 1;   // device -> bemsurg
constexpr std::uint16_t kForceType = 2;  // bemsurg -> device
constexpr std::size_t kPoseBytes = 88;
constexpr std::size_t kForceBytes = 64;

/// A pose packet, bridge to bemsurg: sequence number, channel, sender time, position, orientation and buttons (docs/haptics.md).
/// \ingroup haptics
struct PosePacket {
  std::uint32_t sequence = 0;
  std::uint16_t channel = 0;
  std::uint64_t sender_time_us = 0;  // CLOCK_MONOTONIC (std::chrono::steady_clock) microseconds
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::uint32_t buttons = 0;
};
/// A force packet, bemsurg to bridge: sequence number, channel, sender time, the force, status bits and the pose it answers.
/// \ingroup haptics
struct ForcePacket {
  std::uint32_t sequence = 0;
  std::uint16_t channel = 0;
  std::uint64_t sender_time_us = 0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  std::uint32_t status = 0;         // bit 0: watchdog ramping; bit 1: device disconnected
  std::uint32_t pose_sequence = 0;  // the last pose accepted when this force was computed
};

/// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320).
std::uint32_t crc32(const unsigned char* data, std::size_t bytes) noexcept;
void encode(const PosePacket& p, unsigned char (&out)[kPoseBytes]) noexcept;
void encode(const ForcePacket& p, unsigned char (&out)[kForceBytes]) noexcept;
/// False for a wrong size, magic, version, type or checksum, or non-finite numbers.
bool decode(const unsigned char* data, std::size_t bytes, PosePacket& p) noexcept;
bool decode(const unsigned char* data, std::size_t bytes, ForcePacket& p) noexcept;
std::uint64_t monotonic_us() noexcept;
}  // namespace udp

/// Settings of a UdpDevice: the ports, the channel accepted, when a pose counts as late or the device as disconnected, and
/// the largest force.
/// \ingroup haptics
struct UdpDeviceOptions {
  int listen_port = 0;        // 127.0.0.1 port to bind; 0: any free port (see UdpDevice::port())
  int peer_port = 0;          // the only sender port accepted; 0: the first valid sender is locked in
  std::uint16_t channel = 0;  // packets for another channel are refused as unexpected
  double max_age_s = 0.02;    // a pose older than this on arrival is late
  double lost_after_s = 0.1;  // no valid pose for this long: disconnected (zero force)
  double max_force = 3.3;
};

/// Deprecated name (before 0.2), kept one minor version: use UdpDeviceOptions.

using UdpDeviceSettings [[deprecated("renamed to UdpDeviceOptions in bemsurg 0.2")]] = UdpDeviceOptions;

/// Counts of refused packets (each increments exactly one).
/// \ingroup haptics
struct UdpCounters {
  std::uint64_t accepted = 0, malformed = 0, late = 0, out_of_order = 0, unexpected_sender = 0, send_failures = 0;
  std::uint64_t dropped() const { return malformed + late + out_of_order + unexpected_sender; }
};

/// A haptic device on the other side of a loopback UDP socket, so a separate program holding a vendor SDK drives bemsurg;
/// malformed, late, out-of-order or foreign packets are dropped and counted, never acted on.
/// \ingroup haptics
class UdpDevice : public HapticDevice {
 public:
  static constexpr int kMaxPacketsPerRead = 64;
  /// Binds 127.0.0.1:listen_port (throws IoError with the reason when it cannot).
  explicit UdpDevice(const UdpDeviceOptions& settings = {});
  ~UdpDevice() override;
  UdpDevice(const UdpDevice&) = delete;
  UdpDevice& operator=(const UdpDevice&) = delete;

  std::string name() const override { return "UDP bridge on 127.0.0.1:" + std::to_string(port_); }
  bool available() const override { return fd_ >= 0; }
  std::string why() const override { return "poses arrive over UDP from a bridge program (docs/haptics.md)"; }
  DeviceState read(double session_time) override;
  void write_force(const Eigen::Vector3d& force) override;
  double max_force() const override { return settings_.max_force; }
  std::uint64_t dropped_packets() const override { return counters().dropped(); }

  int port() const { return port_; }
  /// Safe from any thread (relaxed atomic counters).
  UdpCounters counters() const;

 private:
  UdpDeviceOptions settings_;
  int fd_ = -1;
  int port_ = 0;
  std::uint32_t peer_addr_ = 0;  // network order; 0: none yet
  std::uint16_t peer_port_ = 0;  // network order
  bool have_pose_ = false;
  std::uint32_t last_sequence_ = 0;
  std::uint64_t last_accept_us_ = 0;
  std::uint32_t force_sequence_ = 0;
  DeviceState state_;
  std::atomic<std::uint64_t> accepted_{0}, malformed_{0}, late_{0}, out_of_order_{0}, unexpected_{0}, send_failures_{0};
};

/// The bridge program's side (and the tests'): sends poses to a UdpDevice and receives its forces.
/// \ingroup haptics
class UdpBridgeClient {
 public:
  /// Binds 127.0.0.1:local_port (0: any) and sends to 127.0.0.1:device_port.
  UdpBridgeClient(int device_port, int local_port = 0);
  ~UdpBridgeClient();
  UdpBridgeClient(const UdpBridgeClient&) = delete;
  UdpBridgeClient& operator=(const UdpBridgeClient&) = delete;
  int port() const { return port_; }
  /// Stamps sequence (when 0: the next one) and time (when 0: now) and sends.
  void send_pose(udp::PosePacket pose);
  /// Sends raw bytes (tests: malformed packets).
  void send_raw(const unsigned char* data, std::size_t bytes);
  /// Waits up to timeout_s for a valid force packet; false on timeout.
  bool receive_force(udp::ForcePacket& out, double timeout_s);

 private:
  int fd_ = -1;
  int port_ = 0;
  int device_port_ = 0;
  std::uint32_t next_sequence_ = 1;
};

}  // namespace bemsurg::haptics
