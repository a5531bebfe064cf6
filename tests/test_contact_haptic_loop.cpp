// Tests for the haptic hand-over (haptics/triple_buffer.hpp, haptics/haptic_device.hpp; docs/design.md
// §6): snapshots cross threads whole and in order without locks, and the null device works.
#include <array>
#include <atomic>
#include <catch2/catch.hpp>
#include <limits>
#include <thread>

#include "bemsurg/haptics/force_limiter.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/haptics/triple_buffer.hpp"

using namespace bemsurg::haptics;

namespace {
struct Snapshot {
  long sequence = -1;
  std::array<double, 64> values{};  // all equal to sequence when written whole
};
}  // namespace

TEST_CASE("triple buffer: the reader sees whole snapshots, newest first, never older", "[haptics]") {
  TripleBuffer<Snapshot> buffer;
  constexpr long kWrites = 200000;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (long s = 0; s < kWrites; ++s) {
      Snapshot& b = buffer.back();
      b.sequence = s;
      b.values.fill(double(s));
      buffer.publish();
    }
    done = true;
  });
  long last = -1, torn = 0, backwards = 0, seen = 0;
  for (;;) {
    const bool finished = done.load();  // read before acquire: a final publish is then still seen
    if (!buffer.acquire()) {
      if (finished) break;
      continue;
    }
    const Snapshot& f = buffer.front();
    for (double v : f.values)
      if (v != double(f.sequence)) ++torn;
    if (f.sequence < last) ++backwards;
    last = f.sequence;
    ++seen;
  }
  writer.join();
  CHECK(torn == 0);
  CHECK(backwards == 0);
  CHECK(seen > 0);
  CHECK(buffer.front().sequence == kWrites - 1);  // the last publish is never lost
}

TEST_CASE("null device: scripted pose in, limited force out, and it says why it is null", "[haptics]") {
  std::string reason;
  auto device = open_default_device(reason);
  REQUIRE(device);
  CHECK(device->available());
  CHECK(reason.find("null device") != std::string::npos);
  auto* null = dynamic_cast<NullDevice*>(device.get());
  REQUIRE(null != nullptr);
  DeviceState s;
  s.position = Eigen::Vector3d(0.01, 0.02, 0.03);
  null->set_state(s);
  CHECK(device->read(0.0).position == s.position);
  ForceLimiter limit(device->max_force(), 1e12);
  device->write_force(limit(Eigen::Vector3d(0.0, 0.0, 100.0), 1e-3));
  // Clipped to the limit: a scaling by max / |f| and a norm, a few roundings (measured 0).
  CHECK(null->last_force().norm() == Approx(device->max_force()).epsilon(4.0 * std::numeric_limits<double>::epsilon()));
  CHECK(null->writes() == 1);
}
