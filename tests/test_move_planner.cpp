#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "acq/move_planner.h"
#include "core/angles.h"
#include "core/error.h"
#include "test_helpers.h"

using namespace acq;

namespace {

GantryMotion SeedMotion() {
  GantryMotion m;  // 30 deg/s, 60 deg/s^2, settle 0.5 s
  // The seed's published (rounded) directions need 66 and 89 degrees (see docs).
  m.constraints.max_camera_zenith = DegToRad(66);
  m.constraints.max_light_zenith = DegToRad(89);
  m.phi_h_steps = 24;  // every 15 degrees: enough to test, quick
  return m;
}

}  // namespace

TEST_CASE("move times follow the trapezoidal profile, hand computed", "[planner]") {
  GantryMotion m;
  const ArmAngles a{DegToRad(45), 0, 0, 0};
  // 90 degrees of light theta: ramps cover v^2/a = 15 degrees, so 90/30 + 30/60 = 3.5 s, plus
  // 0.5 s settle.
  ArmAngles b = a;
  b.light_theta = DegToRad(135);
  CHECK(m.MoveSeconds(a, b) == Approx(4.0));
  // 10 degrees: a triangle profile, 2 sqrt(10 / 60) = 0.8165 s.
  b = a;
  b.camera_theta = DegToRad(10);
  CHECK(m.MoveSeconds(a, b) == Approx(2 * std::sqrt(10.0 / 60) + 0.5));
  // An azimuth travels straight to the commanded angle, as the firmware moves it: 170 to -170
  // degrees is 340 degrees through 0 (340/30 + 30/60 s), not 20 the shorter way round.
  ArmAngles c = a, d = a;
  c.camera_phi = DegToRad(170);
  d.camera_phi = DegToRad(-170);
  CHECK(m.MoveSeconds(c, d) == Approx(340.0 / 30 + 0.5 + 0.5));
}

TEST_CASE("a move that sweeps one arm through the other is refused", "[planner]") {
  GantryMotion m;
  const ArmAngles from{DegToRad(30), 0, DegToRad(30), DegToRad(90)};
  const ArmAngles to{DegToRad(30), DegToRad(179), DegToRad(30), DegToRad(90)};
  // Both ends are 40+ degrees apart, but the light passes azimuth 90, where the camera is.
  CHECK(m.constraints.Violation(from).empty());
  CHECK(m.constraints.Violation(to).empty());
  CHECK_THAT(m.MoveViolation(from, to), Catch::Contains("deg apart"));
  // 170 to -170 degrees is not the 20 degrees past azimuth 180 but the 340 through 0, where the
  // camera is: the firmware moves the commanded angle straight (the planner once assumed the
  // shorter way round and passed this move).
  const ArmAngles west{DegToRad(30), DegToRad(170), DegToRad(30), 0};
  const ArmAngles east{DegToRad(30), DegToRad(-170), DegToRad(30), 0};
  CHECK(m.constraints.Violation(west).empty());
  CHECK(m.constraints.Violation(east).empty());
  CHECK_THAT(m.MoveViolation(west, east), Catch::Contains("deg apart"));
}

TEST_CASE("a move's safety check agrees with direct trigonometry at every sample", "[planner]") {
  // MoveViolation follows each angle's cosine and sine by rotation from sample to sample; here
  // every sample is checked with cos/sin calls instead, on random moves over the whole range of
  // the arms, some sweeping one arm through the other: both must refuse the same moves.
  const GantryMotion m = SeedMotion();
  const DirectionConstraints& c = m.constraints;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> theta(0, DegToRad(95)), phi(-kPi, kPi);
  int refused = 0, differ = 0;
  for (int i = 0; i < 4000; ++i) {
    const ArmAngles a{theta(rng), phi(rng), theta(rng), phi(rng)};
    const ArmAngles b{theta(rng), phi(rng), theta(rng), phi(rng)};
    // Straight in every commanded angle, azimuths too (the firmware's path).
    const double dlt = b.light_theta - a.light_theta, dlp = b.light_phi - a.light_phi;
    const double dct = b.camera_theta - a.camera_theta, dcp = b.camera_phi - a.camera_phi;
    const double travel = std::max({std::abs(dlt), std::abs(dlp), std::abs(dct), std::abs(dcp)});
    const int steps = std::max(1, int(std::ceil(travel / DegToRad(1))));
    bool direct_refuses = false;
    for (int k = 0; k <= steps && !direct_refuses; ++k) {
      const double t = double(k) / steps;
      const ArmAngles p{a.light_theta + t * dlt, a.light_phi + t * dlp, a.camera_theta + t * dct,
                        a.camera_phi + t * dcp};
      const std::string why = c.Violation(p);
      direct_refuses = !why.empty() && why.find("camera zenith") == std::string::npos;
    }
    const bool refuses = !m.MoveViolation(a, b).empty();
    refused += refuses;
    differ += refuses != direct_refuses;
  }
  CHECK(refused > 400);  // the sample covers both verdicts
  CHECK(refused < 3600);
  CHECK(differ == 0);
}

TEST_CASE("unreachable directions are named with their line and rule", "[planner]") {
  const auto dirs = ReadDirectionsTsv(test::DataPath("directions/seed_directions_20.tsv"));
  GantryMotion m;  // camera <= 65, light <= 85
  CHECK_THROWS_WITH(CheckReachable(dirs, m), Catch::Contains("seed_directions_20.tsv:16") &&
                                                 Catch::Contains("camera zenith 65.1"));
  m.constraints.max_camera_zenith = DegToRad(66);
  CHECK_THROWS_WITH(CheckReachable(dirs, m),
                    Catch::Contains("seed_directions_20.tsv:22") && Catch::Contains("reach"));
}

TEST_CASE("the planned order: every direction once, same measurement, safe, and shorter",
          "[planner]") {
  const auto dirs = ReadDirectionsTsv(test::DataPath("directions/seed_directions_20.tsv"));
  const GantryMotion m = SeedMotion();
  const VisitPlan naive = PlanInFileOrder(dirs, m);
  std::vector<std::size_t> file_order(dirs.size());
  for (std::size_t i = 0; i < dirs.size(); ++i) file_order[i] = i;
  const VisitPlan azimuths = PlanBestAzimuths(dirs, file_order, m);
  const VisitPlan best = PlanShortest(dirs, m);
  WARN("seed's 20: file order " << naive.total_s << " s, best azimuths " << azimuths.total_s
                                << " s, shortest order " << best.total_s << " s");
  CHECK(azimuths.total_s <= naive.total_s);
  CHECK(best.total_s <= azimuths.total_s);
  REQUIRE(best.poses.size() == dirs.size());
  std::vector<int> seen(dirs.size(), 0);
  ArmAngles at = m.home;
  double total = 0;
  for (const PlannedPose& p : best.poses) {
    ++seen[p.index];
    // The pose measures the direction asked for: same Rusinkiewicz angles, whatever phi_h.
    const DirectionPair d = DirectionsOf(p.arms);
    const RusinkiewiczAngles r = RusinkiewiczFromDirections(d.in, d.out);
    CHECK(r.theta_h == Approx(dirs[p.index].angles.theta_h).margin(1e-9));
    CHECK(r.theta_d == Approx(dirs[p.index].angles.theta_d).margin(1e-9));
    // At theta_h = 0 phi_d is undefined (the BRDF does not depend on it there), so rotating the
    // pose may change its phi_d bin; everywhere else the bin must stay.
    if (dirs[p.index].angles.theta_h > 0)
      CHECK(merl::BinOf(r) == merl::BinOf(dirs[p.index].angles));
    CHECK(m.MoveViolation(at, p.arms).empty());
    CHECK(p.move_s == Approx(m.MoveSeconds(at, p.arms)));
    total += p.move_s;
    at = p.arms;
  }
  CHECK(total == Approx(best.total_s));
  for (int s : seen) CHECK(s == 1);
  CHECK(PlanShortest(dirs, m).total_s == best.total_s);  // deterministic
}

TEST_CASE("spread azimuths: the same measurements, half vectors all round, and a longer route",
          "[planner]") {
  const auto dirs = ReadDirectionsTsv(test::DataPath("directions/seed_directions_20.tsv"));
  GantryMotion m = SeedMotion();
  const std::vector<double> target = SpreadHalfVectorAzimuths(dirs, m.phi_h_steps);
  REQUIRE(target.size() == dirs.size());
  CHECK(SpreadHalfVectorAzimuths(dirs, m.phi_h_steps) == target);  // deterministic
  const VisitPlan fastest = PlanShortest(dirs, m);
  m.half_vector_azimuths = HalfVectorAzimuths::kSpread;
  const VisitPlan spread = PlanShortest(dirs, m);
  REQUIRE(spread.poses.size() == dirs.size());
  CHECK(spread.spread_tolerance_deg == kSpreadTolerancesDeg[0]);
  CHECK(fastest.spread_tolerance_deg == 0);
  ArmAngles at = m.home;
  for (const PlannedPose& p : spread.poses) {
    const DirectionPair d = DirectionsOf(p.arms);
    const RusinkiewiczAngles r = RusinkiewiczFromDirections(d.in, d.out);
    CHECK(r.theta_h == Approx(dirs[p.index].angles.theta_h).margin(1e-9));
    CHECK(r.theta_d == Approx(dirs[p.index].angles.theta_d).margin(1e-9));
    // Each pose within the planner's narrowest tolerance of its spread azimuth (free at the
    // pole): the seed's 20 need no wider.
    if (r.theta_h > DegToRad(0.5))
      CHECK(std::abs(std::remainder(r.phi_h - target[p.index], 2 * kPi)) <=
            DegToRad(kSpreadTolerancesDeg[0]) + 1e-6);
    CHECK(m.MoveViolation(at, p.arms).empty());
    at = p.arms;
  }
  // The seed's half vectors lie on one side of the normal when the moves alone decide: a facet
  // tilted 15 degrees the other way is as far from every half vector as from the normal's
  // (15 degrees). Spread, every such facet has one nearer (11.2 degrees measured, 7.3 at 10).
  const double tilt = DegToRad(15);
  CHECK(WidestHalfVectorGap(fastest, tilt) == Approx(tilt).margin(DegToRad(0.3)));
  CHECK(WidestHalfVectorGap(spread, tilt) < DegToRad(12.5));
  // Nothing is free: the spread route is longer (28.2 s against 52.2 s measured).
  CHECK(spread.total_s > fastest.total_s);
  // The name round trip the plan and the CLI use.
  for (HalfVectorAzimuths a : {HalfVectorAzimuths::kFastest, HalfVectorAzimuths::kSpread})
    CHECK(HalfVectorAzimuthsNamed(ToString(a)) == a);
  CHECK_FALSE(HalfVectorAzimuthsNamed("random"));
}

TEST_CASE("spread azimuths widen their tolerance until the route is safe", "[planner]") {
  // tools/run-main.sh's optimised directions: no collision-free route keeps every pose within
  // 10 degrees of its spread azimuth (measured with the default 72 azimuth steps), 20 does.
  const auto dirs = ReadDirectionsTsv(test::Fixture("optimized_directions_20.tsv"));
  GantryMotion m;  // the default limits the directions were optimised for
  m.half_vector_azimuths = HalfVectorAzimuths::kSpread;
  const VisitPlan spread = PlanShortest(dirs, m);
  CHECK(spread.spread_tolerance_deg == kSpreadTolerancesDeg[1]);
  const std::vector<double> target = SpreadHalfVectorAzimuths(dirs, m.phi_h_steps);
  ArmAngles at = m.home;
  int beyond_narrowest = 0;
  for (const PlannedPose& p : spread.poses) {
    const DirectionPair d = DirectionsOf(p.arms);
    const RusinkiewiczAngles r = RusinkiewiczFromDirections(d.in, d.out);
    const double off = std::abs(std::remainder(r.phi_h - target[p.index], 2 * kPi));
    if (r.theta_h > DegToRad(0.5)) {
      CHECK(off <= DegToRad(spread.spread_tolerance_deg) + 1e-6);
      beyond_narrowest += off > DegToRad(kSpreadTolerancesDeg[0]) + 1e-6;
    }
    CHECK(m.MoveViolation(at, p.arms).empty());
    at = p.arms;
  }
  CHECK(beyond_narrowest > 0);  // the wider tolerance was used, not only allowed
}
