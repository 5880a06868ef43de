#include <catch2/catch.hpp>
#include <random>

#include "core/angles.h"
#include "core/rusinkiewicz.h"

using namespace acq;

namespace {

Eigen::Vector3d Spherical(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Directions are unit vectors built from doubles: 1e-12 leaves room for a few rotations'
// rounding and nothing for a wrong sign or axis.
constexpr double kTol = 1e-12;

}  // namespace

TEST_CASE("mirror directions about the normal have theta_h = 0", "[rusinkiewicz]") {
  const double t = DegToRad(30);
  const auto a = RusinkiewiczFromDirections(Spherical(t, 0), Spherical(t, kPi));
  CHECK(a.theta_h == Approx(0).margin(kTol));
  CHECK(a.theta_d == Approx(t).epsilon(kTol));
  CHECK(a.phi_d == Approx(0).margin(kTol));
}

TEST_CASE("light and camera at the same direction: theta_d = 0, theta_h = zenith",
          "[rusinkiewicz]") {
  const auto a = RusinkiewiczFromDirections(Spherical(0.7, 1.1), Spherical(0.7, 1.1));
  CHECK(a.theta_h == Approx(0.7).epsilon(kTol));
  CHECK(a.phi_h == Approx(1.1).epsilon(kTol));
  CHECK(a.theta_d == Approx(0).margin(1e-7));  // acos near 1 loses half the digits
}

TEST_CASE("hand-computed case: light at zenith, camera at 60 degrees", "[rusinkiewicz]") {
  // Half vector at 30 degrees zenith, azimuth 0; w_i is 30 degrees from it, towards -x in the
  // half frame, so phi_d = pi.
  const auto a = RusinkiewiczFromDirections(Spherical(0, 0), Spherical(DegToRad(60), 0));
  CHECK(RadToDeg(a.theta_h) == Approx(30).epsilon(1e-12));
  CHECK(RadToDeg(a.theta_d) == Approx(30).epsilon(1e-12));
  CHECK(std::abs(RadToDeg(a.phi_d)) == Approx(180).epsilon(1e-12));
}

TEST_CASE("directions -> angles -> directions round trip", "[rusinkiewicz]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d in = Spherical(u(rng) * 1.5, u(rng) * 2 * kPi);
    const Eigen::Vector3d out = Spherical(u(rng) * 1.5, u(rng) * 2 * kPi);
    const DirectionPair back = DirectionsFromRusinkiewicz(RusinkiewiczFromDirections(in, out));
    REQUIRE((back.in - in).norm() < 1e-9);
    REQUIRE((back.out - out).norm() < 1e-9);
  }
}

TEST_CASE("angles -> directions -> angles round trip, including the edges", "[rusinkiewicz]") {
  struct Case {
    double th, td, pd;
  };
  const double tiny = 1e-9;
  const Case cases[] = {{0.3, 0.4, 0.0},        {0.3, 0.4, tiny},        {0.3, 0.4, -tiny},
                        {0.3, 0.4, kPi - tiny}, {0.3, 0.4, -kPi + tiny}, {0.3, 0.4, kPi / 2},
                        {1e-6, 0.5, 1.0},       {0.2, 1.2, 2.5}};
  for (const Case& c : cases) {
    RusinkiewiczAngles a;
    a.theta_h = c.th;
    a.theta_d = c.td;
    a.phi_d = c.pd;
    a.phi_h = 0.4;
    const DirectionPair d = DirectionsFromRusinkiewicz(a);
    const auto b = RusinkiewiczFromDirections(d.in, d.out);
    CHECK(b.theta_h == Approx(c.th).epsilon(1e-9));
    CHECK(b.theta_d == Approx(c.td).epsilon(1e-9));
    // phi_d is periodic: compare on the circle.
    CHECK(std::abs(std::remainder(b.phi_d - c.pd, 2 * kPi)) < 1e-8);
  }
}

TEST_CASE("theta_h = 0: phi_h is free, directions still exact", "[rusinkiewicz]") {
  RusinkiewiczAngles a;
  a.theta_h = 0;
  a.theta_d = DegToRad(40);
  a.phi_d = DegToRad(25);
  a.phi_h = 1.3;
  const DirectionPair d = DirectionsFromRusinkiewicz(a);
  // Mirror pair about the normal: same zenith, opposite azimuths.
  CHECK(d.in.z() == Approx(std::cos(a.theta_d)).epsilon(kTol));
  CHECK(d.out.z() == Approx(std::cos(a.theta_d)).epsilon(kTol));
  CHECK((d.in.head<2>() + d.out.head<2>()).norm() < kTol);
  const auto b = RusinkiewiczFromDirections(d.in, d.out);
  CHECK(b.theta_h == Approx(0).margin(1e-7));
  CHECK(b.theta_d == Approx(a.theta_d).epsilon(1e-9));
  // With theta_h = 0 phi_h and phi_d trade off: only phi_h + phi_d is determined.
  CHECK(std::abs(std::remainder(b.phi_h + b.phi_d - a.phi_h - a.phi_d, 2 * kPi)) < 1e-7);
}

TEST_CASE("the horizon test", "[rusinkiewicz]") {
  RusinkiewiczAngles a;
  a.theta_h = DegToRad(60);
  a.theta_d = DegToRad(40);
  a.phi_d = 0;  // w_i tilted further from the normal: 100 degrees
  CHECK_FALSE(AboveHorizon(DirectionsFromRusinkiewicz(a)));
  a.phi_d = kPi / 2;
  CHECK(AboveHorizon(DirectionsFromRusinkiewicz(a)));
}
