#include <catch2/catch.hpp>

#include "core/angles.h"
#include "core/merl_grid.h"
#include "core/merl_grid_lanes.h"
#include "core/rusinkiewicz.h"

#include <cmath>
#include <random>
#include <vector>

using namespace acq;
using namespace acq::merl;

TEST_CASE("theta_h index, hand computed", "[merl]") {
  CHECK(ThetaHIndex(0.0) == 0);
  CHECK(ThetaHIndex(-0.1) == 0);
  CHECK(ThetaHIndex(DegToRad(1)) == 9);      // sqrt(1/90) * 90 = 9.49
  CHECK(ThetaHIndex(DegToRad(10.1)) == 30);  // sqrt(10.1/90) * 90 = 30.15
  CHECK(ThetaHIndex(DegToRad(9.9)) == 29);   // 29.85
  CHECK(ThetaHIndex(DegToRad(45)) == 63);    // sqrt(0.5) * 90 = 63.64
  CHECK(ThetaHIndex(DegToRad(89.9)) == 89);
  CHECK(ThetaHIndex(DegToRad(90)) == 89);  // clamped, as in MERL's reader
}

TEST_CASE("theta_d and phi_d indices, hand computed", "[merl]") {
  CHECK(ThetaDIndex(DegToRad(30.5)) == 30);
  CHECK(ThetaDIndex(DegToRad(89.99)) == 89);
  CHECK(ThetaDIndex(DegToRad(90)) == 89);
  CHECK(PhiDIndex(DegToRad(0.5)) == 0);
  CHECK(PhiDIndex(DegToRad(1.5)) == 1);
  CHECK(PhiDIndex(DegToRad(179.5)) == 179);
  CHECK(PhiDIndex(kPi) == 179);             // phi_d = pi is clamped into the last bin
  CHECK(PhiDIndex(DegToRad(-90.5)) == 89);  // -90.5 + 180 = 89.5 (reciprocity fold)
  CHECK(PhiDIndex(DegToRad(-0.5)) == 179);  // just below 0 folds to just below pi
}

TEST_CASE("flat index layout is phi_d + 180 theta_d + 16200 theta_h", "[merl]") {
  const BinIndex b{1, 2, 3};
  CHECK(b.Flat() == 3 + 180 * 2 + 180 * 90 * 1);
  CHECK(BinFromFlat(b.Flat()) == b);
  CHECK(BinIndex{89, 89, 179}.Flat() == kBins - 1);
}

TEST_CASE("every bin centre falls in its own bin", "[merl]") {
  for (std::size_t i = 0; i < kBins; ++i) {
    const BinIndex b = BinFromFlat(i);
    REQUIRE(BinOf(BinCentre(b)) == b);
  }
}

TEST_CASE("grid geometry: horizon mask and cos weight", "[merl]") {
  const GridGeometry& g = Geometry();
  REQUIRE(g.valid.size() == kBins);
  std::size_t valid = 0;
  for (std::size_t i = 0; i < kBins; ++i) {
    if (!g.valid[i]) {
      REQUIRE(g.cos_weight[i] == 0.0f);
      continue;
    }
    ++valid;
    REQUIRE(g.cos_weight[i] >= float(kCosWeightMin));
    REQUIRE(g.cos_weight[i] <= 1.0f);
  }
  CHECK(valid == g.valid_bins.size());
  // theta_h + theta_d < 90 degrees is always above the horizon; theta_h + theta_d well over 90
  // with phi_d = 0 (w_i tilted further down) never is.
  CHECK(g.valid[BinIndex{10, 20, 0}.Flat()]);
  CHECK_FALSE(g.valid[BinIndex{70, 60, 0}.Flat()]);
  // Normal incidence and reflection: theta_h = theta_d = 0 gives cosw ~ 1.
  CHECK(g.cos_weight[BinIndex{0, 0, 0}.Flat()] == Approx(1.0).epsilon(1e-3));
  // About three quarters of the grid is above the horizon.
  CHECK(double(valid) / kBins > 0.7);
  CHECK(double(valid) / kBins < 0.8);
}

TEST_CASE("angles on bin edges survive a trip through direction vectors", "[merl]") {
  // The seed's directions are whole degrees, exactly on MERL bin edges in theta_d and phi_d.
  for (double td : {16.0, 30.0, 44.0, 63.0}) {
    for (double pd : {0.0, 22.0, 151.0}) {
      RusinkiewiczAngles a;
      a.theta_h = DegToRad(2);
      a.theta_d = DegToRad(td);
      a.phi_d = DegToRad(pd);
      const DirectionPair d = DirectionsFromRusinkiewicz(a);
      INFO("theta_d " << td << " phi_d " << pd);
      CHECK(BinOf(RusinkiewiczFromDirections(d.in, d.out)) == BinOf(a));
      CHECK(BinOf(a).theta_d == int(td));
      CHECK(BinOf(a).phi_d == int(pd));
    }
  }
  CHECK(PhiDIndex(-1e-17) == 0);  // rounding below 0 is 0, not folded to pi
}

TEST_CASE("bins computed in SIMD lanes equal BinOf", "[merl][lanes]") {
  // Random direction pairs over the upper hemisphere, bin centres and bin edges: the lanes
  // version takes the same angles and must give the same bins, edges included.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<RusinkiewiczAngles> angles;
  for (int i = 0; i < 40000; ++i) {
    const double t1 = std::acos(u(rng)), p1 = 2 * kPi * u(rng);
    const double t2 = std::acos(u(rng)), p2 = 2 * kPi * u(rng);
    angles.push_back(
        IsotropicAnglesFromDirections(SphericalDirection(t1, p1), SphericalDirection(t2, p2)));
  }
  for (int b = 0; b < 90; ++b) {
    angles.push_back(BinCentre({b, b, 2 * b}));
    RusinkiewiczAngles edge;  // exactly on edges, and a rounding below them
    edge.theta_h = double(b * b) / (90 * 90) * (kPi / 2);
    edge.theta_d = b * (kPi / 2) / 90;
    edge.phi_d = (2 * b - 90) * kPi / 180;
    angles.push_back(edge);
    edge.theta_d -= 1e-15, edge.phi_d -= 1e-15;
    angles.push_back(edge);
  }
  int differ = 0;
  constexpr int L = kLanes<double>;
  for (std::size_t i = 0; i + L <= angles.size(); i += L) {
    Lanes<double> h, dd, p;
    for (int l = 0; l < L; ++l)
      h[l] = angles[i + l].theta_h, dd[l] = angles[i + l].theta_d, p[l] = angles[i + l].phi_d;
    const LaneMask<double> bins = FlatBinOf<double>(h, dd, p);
    for (int l = 0; l < L; ++l) differ += std::size_t(bins[l]) != BinOf(angles[i + l]).Flat();
  }
  CHECK(differ == 0);
}
