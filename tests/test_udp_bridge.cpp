// Tests for the loopback UDP bridge (haptics/udp_device.hpp, docs/haptics.md "UDP bridge"): poses
// and forces round-trip exactly, and malformed, late, out-of-order and foreign packets are dropped
// and counted, never acted on.
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

#include "bemsurg/error.hpp"
#include "bemsurg/haptics/udp_device.hpp"

using namespace bemsurg::haptics;
using Vec3 = Eigen::Vector3d;

namespace {
/// Reads until the device has taken `accepted + dropped` packets in all (loopback delivery is
/// immediate in practice; the wait only guards against a loaded machine).
DeviceState read_until(UdpDevice& d, std::uint64_t total) {
  DeviceState s = d.read(0.0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (d.counters().accepted + d.counters().dropped() < total && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    s = d.read(0.0);
  }
  return s;
}
}  // namespace

TEST_CASE("the packet format round-trips and its checksum catches a flipped bit", "[haptics][udp]") {
  udp::PosePacket p;
  p.sequence = 77;
  p.channel = 1;
  p.sender_time_us = 123456789;
  p.position = Vec3(0.1, -0.2, 0.3);
  p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec3(0, 1, 0)));
  p.buttons = 5;
  unsigned char buf[udp::kPoseBytes];
  udp::encode(p, buf);
  udp::PosePacket q;
  REQUIRE(udp::decode(buf, sizeof buf, q));
  CHECK(q.sequence == 77);
  CHECK(q.channel == 1);
  CHECK(q.sender_time_us == 123456789);
  CHECK(q.position == p.position);
  CHECK(q.orientation.coeffs().isApprox(p.orientation.coeffs(), 1e-15));  // measured 1.1e-16; bound ~4.5 eps
  CHECK(q.buttons == 5);
  for (std::size_t byte : {std::size_t(0), std::size_t(5), std::size_t(30), std::size_t(85)}) {
    unsigned char bad[udp::kPoseBytes];
    std::copy(buf, buf + sizeof buf, bad);
    bad[byte] ^= 0x10;
    CHECK(!udp::decode(bad, sizeof bad, q));
  }
  CHECK(!udp::decode(buf, sizeof buf - 1, q));
  udp::ForcePacket f;
  f.force = Vec3(1, 2, 3);
  unsigned char fb[udp::kForceBytes];
  udp::encode(f, fb);
  CHECK(!udp::decode(fb, sizeof fb, q));  // a force packet is not a pose
  // The CRC-32 of "123456789" is the standard check value.
  const unsigned char check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  CHECK(udp::crc32(check, 9) == 0xCBF43926U);
}

TEST_CASE("poses and forces round-trip over loopback", "[haptics][udp]") {
  UdpDevice device;
  UdpBridgeClient bridge(device.port());
  CHECK(!device.read(0.0).connected);  // nothing received yet: zero force
  udp::PosePacket p;
  p.position = Vec3(0.01, 0.02, 0.03);
  p.buttons = 1;
  bridge.send_pose(p);
  const DeviceState s = read_until(device, 1);
  CHECK(s.connected);
  CHECK(s.position == p.position);
  CHECK(s.button(0));
  CHECK(device.counters().accepted == 1);
  device.write_force(Vec3(0.5, -0.25, 1.0));
  udp::ForcePacket f;
  REQUIRE(bridge.receive_force(f, 10.0));
  CHECK(f.force == Vec3(0.5, -0.25, 1.0));
  CHECK(f.pose_sequence == 1);
}

TEST_CASE("malformed, late, out-of-order and foreign packets are dropped and counted", "[haptics][udp]") {
  UdpDevice device;
  UdpBridgeClient bridge(device.port());
  udp::PosePacket good;
  good.position = Vec3(0.1, 0.1, 0.1);
  good.sequence = 10;
  bridge.send_pose(good);
  REQUIRE(read_until(device, 1).position == good.position);
  std::uint64_t sent = 1;
  auto expect_unchanged = [&](std::uint64_t total) {
    const DeviceState s = read_until(device, total);
    CHECK(s.position == good.position);
  };
  // Malformed: garbage, and a valid packet with one byte changed.
  const unsigned char garbage[] = {1, 2, 3, 4, 5};
  bridge.send_raw(garbage, sizeof garbage);
  udp::PosePacket moved = good;
  moved.sequence = 11;
  moved.position = Vec3(9, 9, 9);
  moved.sender_time_us = udp::monotonic_us();
  unsigned char buf[udp::kPoseBytes];
  udp::encode(moved, buf);
  buf[40] ^= 1;
  bridge.send_raw(buf, sizeof buf);
  sent += 2;
  expect_unchanged(sent);
  CHECK(device.counters().malformed == 2);
  // Out of order: a sequence number not above the last accepted one.
  moved.sequence = 10;
  bridge.send_pose(moved);
  ++sent;
  expect_unchanged(sent);
  CHECK(device.counters().out_of_order == 1);
  // Late: stamped a second ago.
  moved.sequence = 12;
  moved.sender_time_us = udp::monotonic_us() - 1000000;
  bridge.send_pose(moved);
  ++sent;
  expect_unchanged(sent);
  CHECK(device.counters().late == 1);
  // Foreign: another sender (the first valid one is locked in), and another channel.
  UdpBridgeClient intruder(device.port());
  moved.sequence = 13;
  moved.sender_time_us = 0;
  intruder.send_pose(moved);
  moved.sequence = 14;
  moved.channel = 3;
  bridge.send_pose(moved);
  sent += 2;
  expect_unchanged(sent);
  CHECK(device.counters().unexpected_sender == 2);
  CHECK(device.dropped_packets() == 6);
  CHECK(device.counters().accepted == 1);
  // A good packet is still taken after all that.
  moved.channel = 0;
  moved.sequence = 15;
  bridge.send_pose(moved);
  CHECK(read_until(device, sent + 1).position == Vec3(9, 9, 9));
}

TEST_CASE("a bridge that goes silent disconnects the device", "[haptics][udp]") {
  UdpDeviceOptions settings;
  settings.lost_after_s = 0.02;
  UdpDevice device(settings);
  UdpBridgeClient bridge(device.port());
  bridge.send_pose(udp::PosePacket{});
  REQUIRE(read_until(device, 1).connected);
  // The deadline mechanism, with margin: silent for at least 40 ms (a sleep never ends early)
  // against lost_after_s = 20 ms; a loaded machine only sleeps longer.
  std::this_thread::sleep_for(std::chrono::milliseconds(40));
  CHECK(!device.read(0.0).connected);
}
