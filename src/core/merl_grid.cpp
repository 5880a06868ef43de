#include "core/merl_grid.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"

namespace acq::merl {
namespace {

int ClampIndex(int i, int n) {
  return std::clamp(i, 0, n - 1);
}

int IndexOf(double x, int n) {
  return ClampIndex(int(x + kEdgeSlack), n);
}

}  // namespace

int ThetaHIndex(double theta_h) {
  if (theta_h <= 0.0) return 0;
  return IndexOf(std::sqrt(theta_h / (kPi / 2)) * kThetaH, kThetaH);
}

int ThetaDIndex(double theta_d) {
  if (theta_d <= 0.0) return 0;
  return IndexOf(theta_d / (kPi / 2) * kThetaD, kThetaD);
}

int PhiDIndex(double phi_d) {
  // Reciprocity: the BRDF is unchanged under phi_d -> phi_d + pi.
  // A rounding-size negative phi_d is 0, not pi: the same slack as at the bin edges.
  if (phi_d < -kEdgeSlack * kPi / kPhiD) phi_d += kPi;
  return IndexOf(std::max(phi_d, 0.0) / kPi * kPhiD, kPhiD);
}

BinIndex BinOf(const RusinkiewiczAngles& a) {
  return {ThetaHIndex(a.theta_h), ThetaDIndex(a.theta_d), PhiDIndex(a.phi_d)};
}

BinIndex BinFromFlat(std::size_t flat) {
  BinIndex b;
  b.phi_d = int(flat % kPhiD);
  b.theta_d = int((flat / kPhiD) % kThetaD);
  b.theta_h = int(flat / (std::size_t(kPhiD) * kThetaD));
  return b;
}

RusinkiewiczAngles BinCentre(const BinIndex& b) {
  RusinkiewiczAngles a;
  const double u = (b.theta_h + 0.5) / kThetaH;
  a.theta_h = u * u * (kPi / 2);
  a.theta_d = (b.theta_d + 0.5) * (kPi / 2) / kThetaD;
  a.phi_d = (b.phi_d + 0.5) * kPi / kPhiD;
  a.phi_h = 0.0;
  return a;
}

double CosWeight(const DirectionPair& d) {
  return std::clamp(d.in.z() * d.out.z(), kCosWeightMin, 1.0);
}

const GridGeometry& Geometry() {
  static const GridGeometry geometry = [] {
    GridGeometry g;
    g.valid.assign(kBins, 0);
    g.cos_weight.assign(kBins, 0.0f);
    for (std::size_t i = 0; i < kBins; ++i) {
      const DirectionPair d = DirectionsFromRusinkiewicz(BinCentre(BinFromFlat(i)));
      if (!AboveHorizon(d)) continue;
      g.valid[i] = 1;
      g.cos_weight[i] = float(CosWeight(d));
      g.valid_bins.push_back(std::uint32_t(i));
    }
    return g;
  }();
  return geometry;
}

}  // namespace acq::merl
