#include <catch2/catch.hpp>

#include "brdf/direction_optimizer.h"
#include "brdf/evaluation.h"
#include "brdf/fov_evaluation.h"
#include "core/angles.h"
#include "test_helpers.h"

using namespace acq;

namespace {

// A small basis is enough to exercise the optimiser's rules: 8 materials, 24 rows.
const BasisData& SmallBasis() {
  static const BasisData basis = [] {
    const std::string dir = test::DataPath("nbrdf/merl/");
    MaterialSplit s;
    for (const char* n : {"alum-bronze", "blue-fabric", "gold-paint", "pink-felt", "teflon",
                          "chrome", "red-fabric", "white-marble"})
      s.training.push_back({n, dir + n + ".h5"});
    BasisOptions o;
    o.components = 24;
    o.progress = false;
    return BuildBasis(s, o);
  }();
  return basis;
}

// Checked from the vectors, not through DirectionConstraints::Violation.
void RequireWithinConstraints(const ArmAngles& arms, const DirectionConstraints& c) {
  const DirectionPair d = DirectionsOf(arms);
  REQUIRE(d.in.z() > 0);
  REQUIRE(d.out.z() > 0);
  REQUIRE(std::acos(d.out.z()) <= c.max_camera_zenith + 1e-12);
  REQUIRE(std::acos(d.in.z()) <= c.max_light_zenith + 1e-12);
  REQUIRE(std::acos(d.in.dot(d.out)) >= c.min_separation - 1e-12);
  REQUIRE(arms.camera_theta <= arms.light_theta + 1e-12);  // camera on the smaller zenith
}

}  // namespace

TEST_CASE("optimised directions satisfy every constraint, arm angles included", "[optimizer]") {
  OptimizerOptions o;
  o.n = 12;
  o.candidates = 200;
  o.progress = false;
  o.constraints.max_camera_zenith = DegToRad(50);
  o.constraints.max_light_zenith = DegToRad(70);
  o.constraints.min_separation = DegToRad(35);
  for (Score score : {Score::kCondition, Score::kExpectedError}) {
    o.score = score;
    const auto result = OptimizeDirections(SmallBasis().View(), o);
    REQUIRE(result.directions.size() == 12);
    for (const Direction& d : result.directions)
      RequireWithinConstraints(ArmAnglesFor(d.angles), o.constraints);
    // And through the TSV the user gets: re-read angles give the same arm angles.
    test::TempDir dir;
    WriteDirectionsTsv(result.directions, dir / "d.tsv", "test");
    for (const Direction& d : ReadDirectionsTsv(dir / "d.tsv"))
      RequireWithinConstraints(ArmAnglesFor(d.angles), o.constraints);
  }
}

TEST_CASE("the optimiser is deterministic for a seed, and beats random sets", "[optimizer]") {
  OptimizerOptions o;
  o.n = 10;
  o.candidates = 200;
  o.progress = false;
  o.score = Score::kCondition;
  const auto a = OptimizeDirections(SmallBasis().View(), o);
  const auto b = OptimizeDirections(SmallBasis().View(), o);
  CHECK(BinsOf(a.directions) == BinsOf(b.directions));
  CHECK(a.condition == b.condition);
  o.seed = 2;
  CHECK(BinsOf(OptimizeDirections(SmallBasis().View(), o).directions) != BinsOf(a.directions));
  // Reported condition number is the real one of the output set.
  CHECK(ConditionOfBins(SmallBasis().View(), BinsOf(a.directions), 10) == Approx(a.condition));
  for (std::uint64_t s = 1; s <= 5; ++s)
    CHECK(ConditionOfBins(SmallBasis().View(), BinsOf(RandomDirections(10, s)), 10) > a.condition);
}

TEST_CASE("field-of-view-aware optimisation keeps every position within the horizon",
          "[optimizer]") {
  OptimizerOptions o;
  o.n = 6;
  o.candidates = 100;
  o.progress = false;
  o.geometry.sample_size_mm = NearFieldGeometry::SampleSizeForFov(DegToRad(10), 1000);
  const auto result = OptimizeDirections(SmallBasis().View(), o);
  REQUIRE(result.directions.size() == 6);
  for (const Direction& d : result.directions)
    for (const auto& p : o.geometry.Positions(o.fov_grid))
      CHECK(AboveHorizon(o.geometry.DirectionsAt(DirectionsOf(ArmAnglesFor(d.angles)), p)));
}

TEST_CASE("impossible requests are refused with the reason", "[optimizer]") {
  OptimizerOptions o;
  o.n = 5;
  o.k = 6;
  CHECK_THROWS_WITH(OptimizeDirections(SmallBasis().View(), o), Catch::Contains("k > n"));
  o.k = 0;
  o.constraints.max_camera_zenith = DegToRad(2);
  o.constraints.min_separation = DegToRad(170);
  o.progress = false;
  CHECK_THROWS_WITH(OptimizeDirections(SmallBasis().View(), o),
                    Catch::Contains("satisfy the constraints"));
}

TEST_CASE("closed-form field-of-view error equals the direct reconstruction", "[fov]") {
  // At zero field of view the closed form must reproduce EvaluateHomogeneous's grid RMSE; both
  // are double sums over float32 rows, so 1e-6 relative is rounding, not method.
  const BasisData& basis = SmallBasis();
  std::vector<MerlBrdf> truths = {LoadMaterial({"brass", test::DataPath("nbrdf/merl/brass.h5")})};
  const HeldOutSet held(basis.View(), truths);
  const auto directions = RandomDirections(30, 9);
  FovEvalOptions o;
  o.ridge.components = 20;
  const FovResult fov = EvaluateOverFov(held, directions, o);
  const auto direct = EvaluateHomogeneous(basis.View(), truths[0], BinsOf(directions), o.ridge);
  for (int c = 0; c < 3; ++c)
    CHECK(fov.channel_log_rmse[c] == Approx(direct[c].log_rmse).epsilon(1e-6));
  CHECK(fov.condition_centre == Approx(direct[0].condition));
}

TEST_CASE("where the method fails: n < k, bunched directions, eta = 0, noise", "[fov]") {
  const BasisData& basis = SmallBasis();
  std::vector<MerlBrdf> truths = {LoadMaterial({"brass", test::DataPath("nbrdf/merl/brass.h5")})};
  const HeldOutSet held(basis.View(), truths);
  FovEvalOptions o;
  o.ridge.components = 20;
  // Too few directions: infinite condition, but ridge keeps the answer finite.
  const FovResult few = EvaluateOverFov(held, RandomDirections(10, 1), o);
  CHECK(std::isinf(few.condition_centre));
  CHECK(std::isfinite(few.channel_log_rmse[0]));
  // Bunched: 20 directions within a degree or two of each other.
  std::vector<Direction> bunched;
  for (int i = 0; i < 20; ++i) {
    RusinkiewiczAngles a;
    a.theta_h = DegToRad(20 + 0.1 * i);
    a.theta_d = DegToRad(30 + 0.05 * i);
    a.phi_d = DegToRad(90 + 0.1 * i);
    bunched.push_back({a, "bunched"});
  }
  const FovResult spread = EvaluateOverFov(held, RandomDirections(20, 1), o);
  const FovResult tight = EvaluateOverFov(held, bunched, o);
  CHECK(tight.condition_centre > 100 * spread.condition_centre);
  CHECK(tight.channel_log_rmse[0] > spread.channel_log_rmse[0]);
  // eta = 0 with a well-posed set: finite; noise makes the error grow monotonically.
  o.ridge.eta = 0;
  CHECK(std::isfinite(EvaluateOverFov(held, RandomDirections(40, 2), o).channel_log_rmse[0]));
  // Noise on a well-posed set (60 directions for 20 components): each level is 3x the last, so
  // the error's growth dwarfs the spread of the 8-trial average.
  o.ridge.eta = 40;
  double previous = 0;
  for (double sigma : {0.0, 0.3, 1.0, 3.0}) {
    o.noise_sigma = sigma;
    const double e = EvaluateOverFov(held, RandomDirections(60, 3), o).channel_log_rmse[0];
    CHECK(e > previous);
    previous = e;
  }
}
