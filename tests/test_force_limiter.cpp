// The force limiter (bemsurg/haptics/force_limiter.hpp), the last stage before a haptic device:
// whatever it is asked for, the output is finite, at most max_force, and changes by at most
// max_rate * dt per call (a rate per second); a NaN holds the last force and a huge finite request ramps up to the limit.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "bemsurg/haptics/force_limiter.hpp"
#include "support/test_constants.hpp"

using bemsurg::haptics::ForceLimiter;

namespace {
const double kMaxForce = 3.0, kMaxRate = 500.0, kDt = 1e-3, kMaxStep = kMaxRate * kDt;
using bemsurg_test::kEps;
// Relative slack of the step and size checks: |f| <= 3 N and the step 0.5 N, so f - last carries
// about 2 eps x 3 N of rounding (12 eps of the step) and each clip (a scaling and a norm) 3 eps:
// 16 eps. Measured: at most 2 eps above the step, never above max_force.
const double kSlack = 16 * kEps;
}  // namespace

TEST_CASE("a huge finite request ramps to max_force instead of freezing", "[haptics][limiter]") {
  for (double huge : {1e200, -1e200, 1e300, std::numeric_limits<double>::max()}) {
    INFO(huge);
    ForceLimiter limit(kMaxForce, kMaxRate);
    Eigen::Vector3d last = Eigen::Vector3d::Zero();
    for (int k = 0; k < 20; ++k) {
      const Eigen::Vector3d f = limit(Eigen::Vector3d(huge, huge, 0.0), kDt);
      REQUIRE(f.allFinite());
      CHECK((f - last).norm() <= kMaxStep * (1.0 + kSlack));
      CHECK(f.norm() <= kMaxForce * (1.0 + kSlack));
      last = f;
    }
    CHECK(last.norm() == Approx(kMaxForce).epsilon(4 * kEps));                                     // measured 1.1e-16
    CHECK(last.x() == Approx(std::copysign(kMaxForce / std::sqrt(2.0), huge)).epsilon(4 * kEps));  // measured 0
  }
}

TEST_CASE("a non-finite request holds the last force", "[haptics][limiter]") {
  ForceLimiter limit(kMaxForce, kMaxRate);
  const Eigen::Vector3d held = limit(Eigen::Vector3d(0.0, 0.3, 0.0), kDt);
  CHECK(held.y() == Approx(0.3).epsilon(2 * kEps));  // inside both limits: 0 + (0.3 - 0), measured 0
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& bad : {Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(0, inf, 0), Eigen::Vector3d(-inf, nan, 1)})
    CHECK(limit(bad, kDt) == held);
  limit.reset();
  CHECK(limit(Eigen::Vector3d(nan, nan, nan), kDt) == Eigen::Vector3d::Zero());
}

TEST_CASE("any sequence of requests stays within max_force and max_step", "[haptics][limiter]") {
  ForceLimiter limit(kMaxForce, kMaxRate);
  Eigen::Vector3d last = Eigen::Vector3d::Zero();
  std::srand(7);
  for (int k = 0; k < 2000; ++k) {
    const double scale = std::pow(10.0, double(k % 13) * 25.0 - 150.0);  // 1e-150 .. 1e150
    const Eigen::Vector3d request = scale * Eigen::Vector3d::Random();
    const Eigen::Vector3d f = limit(request, kDt);
    REQUIRE(f.allFinite());
    CHECK((f - last).norm() <= kMaxStep * (1.0 + kSlack));
    CHECK(f.norm() <= kMaxForce * (1.0 + kSlack));
    last = f;
  }
  // A small request is met exactly once the ramp has reached it.
  for (int k = 0; k < 20; ++k) last = limit(Eigen::Vector3d(0.1, -0.2, 0.05), kDt);
  // last + (request - last): one rounding per component (measured 0).
  CHECK((last - Eigen::Vector3d(0.1, -0.2, 0.05)).norm() <= 4 * kEps * Eigen::Vector3d(0.1, -0.2, 0.05).norm());
}

TEST_CASE("the rate limit is per second: the same ramp at 1 kHz and 10 kHz", "[haptics][limiter]") {
  // 0.5 s of a 2 N step request at 1 kHz and at 10 kHz: both reach max_rate * t = 1 N
  // (5 N/s), independent of the rate; a per-call step would have made the 10 kHz loop 10x faster.
  for (double rate : {1000.0, 10000.0}) {
    INFO(rate);
    ForceLimiter limit(kMaxForce, 2.0);
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    const int n = static_cast<int>(0.5 * rate);
    for (int k = 0; k < n; ++k) f = limit(Eigen::Vector3d(0, 0, 2.0), 1.0 / rate);
    // 0.5 rate steps added one by one, each rounding by at most eps of the sum (<= 1 N): n eps with
    // n = 0.5 rate (measured 6.7e-16 at 1 kHz, 7.7e-14 at 10 kHz).
    CHECK(f.z() == Approx(1.0).epsilon(0.5 * rate * kEps));
  }
  ForceLimiter limit(kMaxForce, 2.0);
  CHECK(limit(Eigen::Vector3d(0, 0, 1), -1e-3) == Eigen::Vector3d::Zero());  // a negative dt holds
  CHECK(limit(Eigen::Vector3d(0, 0, 1), std::numeric_limits<double>::quiet_NaN()) == Eigen::Vector3d::Zero());
}
