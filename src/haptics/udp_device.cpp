// Implementation of bemsurg/haptics/udp_device.hpp: the loopback UDP bridge (docs/haptics.md).
// Integers are written little-endian byte by byte; doubles as their IEEE-754 bit patterns, also
// little-endian, so the format does not depend on the host's byte order.
#include "bemsurg/haptics/udp_device.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>

#include "bemsurg/error.hpp"

namespace bemsurg::haptics {

namespace udp {
namespace {
struct CrcTable {
  std::uint32_t v[256];
  constexpr CrcTable() : v{} {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1U) ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      v[i] = c;
    }
  }
};
constexpr CrcTable kCrc;

void put_u16(unsigned char* p, std::uint16_t x) {
  p[0] = static_cast<unsigned char>(x);
  p[1] = static_cast<unsigned char>(x >> 8);
}
void put_u32(unsigned char* p, std::uint32_t x) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(x >> (8 * i));
}
void put_u64(unsigned char* p, std::uint64_t x) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(x >> (8 * i));
}
void put_f64(unsigned char* p, double d) {
  std::uint64_t x;
  std::memcpy(&x, &d, 8);
  put_u64(p, x);
}
std::uint16_t get_u16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
std::uint32_t get_u32(const unsigned char* p) {
  std::uint32_t x = 0;
  for (int i = 0; i < 4; ++i) x |= static_cast<std::uint32_t>(p[i]) << (8 * i);
  return x;
}
std::uint64_t get_u64(const unsigned char* p) {
  std::uint64_t x = 0;
  for (int i = 0; i < 8; ++i) x |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return x;
}
double get_f64(const unsigned char* p) {
  const std::uint64_t x = get_u64(p);
  double d;
  std::memcpy(&d, &x, 8);
  return d;
}
void put_header(unsigned char* p, std::uint16_t type, std::uint32_t seq, std::uint16_t channel, std::uint64_t t) {
  put_u32(p, kMagic);
  put_u16(p + 4, kVersion);
  put_u16(p + 6, type);
  put_u32(p + 8, seq);
  put_u16(p + 12, channel);
  put_u16(p + 14, 0);
  put_u64(p + 16, t);
}
bool check_header(const unsigned char* p, std::size_t bytes, std::size_t want, std::uint16_t type) {
  if (bytes != want) return false;
  if (get_u32(p) != kMagic || get_u16(p + 4) != kVersion || get_u16(p + 6) != type) return false;
  return crc32(p, want - 4) == get_u32(p + want - 4);
}
}  // namespace

std::uint32_t crc32(const unsigned char* data, std::size_t bytes) noexcept {
  std::uint32_t c = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < bytes; ++i) c = kCrc.v[(c ^ data[i]) & 0xFFU] ^ (c >> 8);
  return c ^ 0xFFFFFFFFU;
}

void encode(const PosePacket& p, unsigned char (&out)[kPoseBytes]) noexcept {
  put_header(out, kPoseType, p.sequence, p.channel, p.sender_time_us);
  for (int i = 0; i < 3; ++i) put_f64(out + 24 + 8 * i, p.position(i));
  put_f64(out + 48, p.orientation.w());
  put_f64(out + 56, p.orientation.x());
  put_f64(out + 64, p.orientation.y());
  put_f64(out + 72, p.orientation.z());
  put_u32(out + 80, p.buttons);
  put_u32(out + 84, crc32(out, 84));
}

void encode(const ForcePacket& p, unsigned char (&out)[kForceBytes]) noexcept {
  put_header(out, kForceType, p.sequence, p.channel, p.sender_time_us);
  for (int i = 0; i < 3; ++i) put_f64(out + 24 + 8 * i, p.force(i));
  put_u32(out + 48, p.status);
  put_u32(out + 52, 0);
  put_u32(out + 56, p.pose_sequence);
  put_u32(out + 60, crc32(out, 60));
}

bool decode(const unsigned char* d, std::size_t bytes, PosePacket& p) noexcept {
  if (!check_header(d, bytes, kPoseBytes, kPoseType)) return false;
  PosePacket q;
  q.sequence = get_u32(d + 8);
  q.channel = get_u16(d + 12);
  q.sender_time_us = get_u64(d + 16);
  for (int i = 0; i < 3; ++i) q.position(i) = get_f64(d + 24 + 8 * i);
  q.orientation = Eigen::Quaterniond(get_f64(d + 48), get_f64(d + 56), get_f64(d + 64), get_f64(d + 72));
  q.buttons = get_u32(d + 80);
  if (!q.position.allFinite() || !q.orientation.coeffs().allFinite() || !(q.orientation.norm() > 0.5)) return false;
  q.orientation.normalize();
  p = q;
  return true;
}

bool decode(const unsigned char* d, std::size_t bytes, ForcePacket& p) noexcept {
  if (!check_header(d, bytes, kForceBytes, kForceType)) return false;
  ForcePacket q;
  q.sequence = get_u32(d + 8);
  q.channel = get_u16(d + 12);
  q.sender_time_us = get_u64(d + 16);
  for (int i = 0; i < 3; ++i) q.force(i) = get_f64(d + 24 + 8 * i);
  q.status = get_u32(d + 48);
  q.pose_sequence = get_u32(d + 56);
  if (!q.force.allFinite()) return false;
  p = q;
  return true;
}

std::uint64_t monotonic_us() noexcept {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
}
}  // namespace udp

namespace {
int open_loopback_socket(int port, int& bound_port, const char* who) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) throw IoError(std::string(who) + ": cannot create a UDP socket: " + std::strerror(errno));
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    throw IoError(std::string(who) + ": cannot bind 127.0.0.1:" + std::to_string(port) + ": " + why);
  }
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  bound_port = ntohs(a.sin_port);
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL, 0) | O_NONBLOCK);
  return fd;
}
}  // namespace

UdpDevice::UdpDevice(const UdpDeviceOptions& settings) : settings_(settings) {
  if (settings.listen_port < 0 || settings.listen_port > 65535 || settings.peer_port < 0 || settings.peer_port > 65535)
    throw InvalidArgumentError("UdpDevice: ports must lie in [0, 65535]");
  if (!(settings.max_age_s > 0.0) || !(settings.lost_after_s > 0.0) || !(settings.max_force > 0.0))
    throw InvalidArgumentError("UdpDevice: max_age_s, lost_after_s and max_force must be positive");
  fd_ = open_loopback_socket(settings.listen_port, port_, "UdpDevice");
  state_.connected = false;
}

UdpDevice::~UdpDevice() {
  if (fd_ >= 0) ::close(fd_);
}

DeviceState UdpDevice::read(double) {
  unsigned char buf[256];
  const std::uint64_t now = udp::monotonic_us();
  const std::uint64_t max_age = static_cast<std::uint64_t>(settings_.max_age_s * 1e6);
  for (int i = 0; i < kMaxPacketsPerRead; ++i) {
    sockaddr_in from{};
    socklen_t len = sizeof from;
    const ssize_t n = ::recvfrom(fd_, buf, sizeof buf, MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&from), &len);
    if (n < 0) break;  // EAGAIN: drained
    udp::PosePacket p;
    if (!udp::decode(buf, static_cast<std::size_t>(n), p)) {
      malformed_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    const bool loopback = from.sin_addr.s_addr == htonl(INADDR_LOOPBACK);
    const bool port_ok =
        peer_port_ != 0 ? from.sin_port == peer_port_ : (settings_.peer_port == 0 || ntohs(from.sin_port) == settings_.peer_port);
    if (!loopback || !port_ok || p.channel != settings_.channel) {
      unexpected_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (have_pose_ && p.sequence <= last_sequence_) {
      out_of_order_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (p.sender_time_us > now + max_age || now - p.sender_time_us > max_age) {
      late_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    peer_addr_ = from.sin_addr.s_addr;
    peer_port_ = from.sin_port;  // locked in: later packets from elsewhere are unexpected
    have_pose_ = true;
    last_sequence_ = p.sequence;
    last_accept_us_ = now;
    state_.position = p.position;
    state_.orientation = p.orientation;
    state_.direction = p.orientation * Eigen::Vector3d(0, 0, -1);
    state_.buttons = p.buttons;
    accepted_.fetch_add(1, std::memory_order_relaxed);
  }
  state_.connected = have_pose_ && now - last_accept_us_ <= static_cast<std::uint64_t>(settings_.lost_after_s * 1e6);
  return state_;
}

void UdpDevice::write_force(const Eigen::Vector3d& force) {
  if (peer_port_ == 0) return;  // nobody to tell yet
  udp::ForcePacket f;
  f.sequence = ++force_sequence_;
  f.channel = settings_.channel;
  f.sender_time_us = udp::monotonic_us();
  f.force = force;
  f.status = state_.connected ? 0U : 2U;
  f.pose_sequence = last_sequence_;
  unsigned char buf[udp::kForceBytes];
  udp::encode(f, buf);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = peer_addr_;
  to.sin_port = peer_port_;
  if (::sendto(fd_, buf, sizeof buf, MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&to), sizeof to) != static_cast<ssize_t>(sizeof buf))
    send_failures_.fetch_add(1, std::memory_order_relaxed);
}

UdpCounters UdpDevice::counters() const {
  UdpCounters c;
  c.accepted = accepted_.load(std::memory_order_relaxed);
  c.malformed = malformed_.load(std::memory_order_relaxed);
  c.late = late_.load(std::memory_order_relaxed);
  c.out_of_order = out_of_order_.load(std::memory_order_relaxed);
  c.unexpected_sender = unexpected_.load(std::memory_order_relaxed);
  c.send_failures = send_failures_.load(std::memory_order_relaxed);
  return c;
}

// ---- client ------------------------------------------------------------------------------------

UdpBridgeClient::UdpBridgeClient(int device_port, int local_port) : device_port_(device_port) {
  fd_ = open_loopback_socket(local_port, port_, "UdpBridgeClient");
}

UdpBridgeClient::~UdpBridgeClient() {
  if (fd_ >= 0) ::close(fd_);
}

void UdpBridgeClient::send_raw(const unsigned char* data, std::size_t bytes) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  to.sin_port = htons(static_cast<std::uint16_t>(device_port_));
  if (::sendto(fd_, data, bytes, 0, reinterpret_cast<sockaddr*>(&to), sizeof to) != static_cast<ssize_t>(bytes))
    throw IoError(std::string("UdpBridgeClient: sendto failed: ") + std::strerror(errno));
}

void UdpBridgeClient::send_pose(udp::PosePacket pose) {
  if (pose.sequence == 0) pose.sequence = next_sequence_;
  next_sequence_ = pose.sequence + 1;
  if (pose.sender_time_us == 0) pose.sender_time_us = udp::monotonic_us();
  unsigned char buf[udp::kPoseBytes];
  udp::encode(pose, buf);
  send_raw(buf, sizeof buf);
}

bool UdpBridgeClient::receive_force(udp::ForcePacket& out, double timeout_s) {
  const std::uint64_t deadline = udp::monotonic_us() + static_cast<std::uint64_t>(timeout_s * 1e6);
  unsigned char buf[256];
  for (;;) {
    const std::uint64_t now = udp::monotonic_us();
    if (now >= deadline) return false;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>((deadline - now) / 1000 + 1)) <= 0) continue;
    const ssize_t n = ::recv(fd_, buf, sizeof buf, MSG_DONTWAIT);
    if (n > 0 && udp::decode(buf, static_cast<std::size_t>(n), out)) return true;
  }
}

}  // namespace bemsurg::haptics
