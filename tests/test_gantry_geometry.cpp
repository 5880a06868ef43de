#include <catch2/catch.hpp>

#include "core/angles.h"
#include "core/gantry_geometry.h"

using namespace acq;

TEST_CASE("arm angles: the camera takes the smaller zenith, and they round-trip", "[gantry]") {
  RusinkiewiczAngles a;
  a.theta_h = DegToRad(20);
  a.theta_d = DegToRad(40);
  a.phi_d = DegToRad(10);  // w_i tilts away from the normal: light lower than camera
  const ArmAngles arms = ArmAnglesFor(a);
  CHECK(arms.camera_theta <= arms.light_theta);
  const DirectionPair d = DirectionsOf(arms);
  const RusinkiewiczAngles back = RusinkiewiczFromDirections(d.out, d.in);  // reciprocity
  const RusinkiewiczAngles fwd = RusinkiewiczFromDirections(d.in, d.out);
  CHECK(fwd.theta_h == Approx(a.theta_h).epsilon(1e-9));
  CHECK(fwd.theta_d == Approx(a.theta_d).epsilon(1e-9));
  CHECK(back.theta_d == Approx(a.theta_d).epsilon(1e-9));
}

TEST_CASE("constraint violations name the rule", "[gantry]") {
  DirectionConstraints c;
  ArmAngles arms{DegToRad(40), 0, DegToRad(70), kPi};
  CHECK_THAT(c.Violation(arms), Catch::Contains("camera zenith 70.000"));
  arms = {DegToRad(88), 0, DegToRad(30), kPi};
  CHECK_THAT(c.Violation(arms), Catch::Contains("reach"));
  arms = {DegToRad(30), 0, DegToRad(35), 0};  // 5 degrees apart
  CHECK_THAT(c.Violation(arms), Catch::Contains("5.000 deg apart"));
  arms = {DegToRad(95), 0, DegToRad(30), kPi};
  CHECK_THAT(c.Violation(arms), Catch::Contains("below the horizon"));
  arms = {DegToRad(40), 0, DegToRad(30), kPi};
  CHECK(c.Violation(arms).empty());
  c.enabled = false;  // only the horizon remains
  arms = {DegToRad(40), 0, DegToRad(80), kPi};
  CHECK(c.Violation(arms).empty());
}

TEST_CASE("near field: the centre sees the arms' directions, corners see others", "[gantry]") {
  NearFieldGeometry g;
  g.camera_distance_mm = 1000;
  g.light_distance_mm = 500;
  g.sample_size_mm = NearFieldGeometry::SampleSizeForFov(DegToRad(10), 1000);
  CHECK(g.sample_size_mm == Approx(2 * 1000 * std::tan(DegToRad(5))));
  const auto positions = g.Positions(10);
  REQUIRE(positions.size() == 100);
  const ArmAngles arms{DegToRad(30), 0, 0, 0};  // camera overhead
  const DirectionPair centre = g.DirectionsAt(DirectionsOf(arms), {0, 0});
  CHECK((centre.out - Eigen::Vector3d(0, 0, 1)).norm() < 1e-12);
  // A point at x = 50 mm sees the overhead camera 50/1000 rad off the normal, towards -x.
  const DirectionPair off = g.DirectionsAt(DirectionsOf(arms), {50, 0});
  CHECK(std::atan2(-off.out.x(), off.out.z()) == Approx(std::atan(0.05)).epsilon(1e-12));
  CHECK(NearFieldGeometry{}.Positions(10).size() == 1);  // no sample size: the centre only
}
