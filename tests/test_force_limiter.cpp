// The force limiter (bemsurg/haptics/force_limiter.hpp), the last stage before a haptic device:
// whatever it is asked for, the output is finite, at most max_force, and changes by at most
// max_step per call; a NaN holds the last force and a huge finite request ramps up to the limit.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "bemsurg/haptics/force_limiter.hpp"

using bemsurg::haptics::ForceLimiter;

namespace {
const double kMaxForce = 3.0, kMaxStep = 0.5;
const double kSlack = 1e-12;
}  // namespace

TEST_CASE("a huge finite request ramps to max_force instead of freezing", "[haptics][limiter]") {
  for (double huge : {1e200, -1e200, 1e300, std::numeric_limits<double>::max()}) {
    INFO(huge);
    ForceLimiter limit(kMaxForce, kMaxStep);
    Eigen::Vector3d last = Eigen::Vector3d::Zero();
    for (int k = 0; k < 20; ++k) {
      const Eigen::Vector3d f = limit(Eigen::Vector3d(huge, huge, 0.0));
      REQUIRE(f.allFinite());
      CHECK((f - last).norm() <= kMaxStep * (1.0 + kSlack));
      CHECK(f.norm() <= kMaxForce * (1.0 + kSlack));
      last = f;
    }
    CHECK(last.norm() == Approx(kMaxForce));
    CHECK(last.x() == Approx(std::copysign(kMaxForce / std::sqrt(2.0), huge)));
  }
}

TEST_CASE("a non-finite request holds the last force", "[haptics][limiter]") {
  ForceLimiter limit(kMaxForce, kMaxStep);
  const Eigen::Vector3d held = limit(Eigen::Vector3d(0.0, 0.3, 0.0));
  CHECK(held.y() == Approx(0.3));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& bad : {Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(0, inf, 0), Eigen::Vector3d(-inf, nan, 1)})
    CHECK(limit(bad) == held);
  limit.reset();
  CHECK(limit(Eigen::Vector3d(nan, nan, nan)) == Eigen::Vector3d::Zero());
}

TEST_CASE("any sequence of requests stays within max_force and max_step", "[haptics][limiter]") {
  ForceLimiter limit(kMaxForce, kMaxStep);
  Eigen::Vector3d last = Eigen::Vector3d::Zero();
  std::srand(7);
  for (int k = 0; k < 2000; ++k) {
    const double scale = std::pow(10.0, double(k % 13) * 25.0 - 150.0);  // 1e-150 .. 1e150
    const Eigen::Vector3d request = scale * Eigen::Vector3d::Random();
    const Eigen::Vector3d f = limit(request);
    REQUIRE(f.allFinite());
    CHECK((f - last).norm() <= kMaxStep * (1.0 + kSlack));
    CHECK(f.norm() <= kMaxForce * (1.0 + kSlack));
    last = f;
  }
  // A small request is met exactly once the ramp has reached it.
  for (int k = 0; k < 20; ++k) last = limit(Eigen::Vector3d(0.1, -0.2, 0.05));
  CHECK((last - Eigen::Vector3d(0.1, -0.2, 0.05)).norm() < 1e-15);
}
