#include <catch2/catch.hpp>

#include "core/motion_profile.h"

using namespace acq;

TEST_CASE("trapezoidal profile: ends where it should, never overshoots, continuous", "[motion]") {
  const TrapezoidProfile p{30, 60};  // deg/s, deg/s^2: ramps cover 15 degrees
  for (double d : {-120.0, -10.0, 0.5, 15.0, 90.0}) {
    const double T = p.Duration(d);
    CHECK(p.Position(d, 0) == 0);
    CHECK(p.Position(d, T) == Approx(d));
    CHECK(p.Position(d, T + 1) == Approx(d));
    double last = 0;
    for (int i = 1; i <= 1000; ++i) {
      const double x = p.Position(d, T * i / 1000);
      // Monotonic towards the target and no jumps bigger than the top speed allows.
      REQUIRE(std::abs(x) >= std::abs(last) - 1e-12);
      REQUIRE(std::abs(x) <= std::abs(d) + 1e-12);
      REQUIRE(std::abs(x - last) <= p.speed * T / 1000 + 1e-9);
      last = x;
    }
  }
  CHECK(p.Duration(90) == Approx(90.0 / 30 + 30.0 / 60));     // cruise reached
  CHECK(p.Duration(10) == Approx(2 * std::sqrt(10.0 / 60)));  // triangle
}
