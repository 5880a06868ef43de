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

std::array<Corner, 8> InterpolationCorners(const RusinkiewiczAngles& a) {
  // Index coordinates in which the bin centres are the integers.
  const double phi = a.phi_d < 0 ? a.phi_d + kPi : a.phi_d;
  const double h = std::sqrt(std::max(a.theta_h, 0.0) / (kPi / 2)) * kThetaH - 0.5;
  const double d = a.theta_d / (kPi / 2) * kThetaD - 0.5, p = phi / kPi * kPhiD - 0.5;
  const int h0 = int(std::floor(h)), d0 = int(std::floor(d)), p0 = int(std::floor(p));
  const double fh = h - h0, fd = d - d0, fp = p - p0;
  std::array<Corner, 8> corners;
  for (int corner = 0; corner < 8; ++corner) {
    const int dh = corner & 1, dd = (corner >> 1) & 1, dp = (corner >> 2) & 1;
    BinIndex b;
    b.theta_h = ClampIndex(h0 + dh, kThetaH);
    b.theta_d = ClampIndex(d0 + dd, kThetaD);
    b.phi_d = ((p0 + dp) % kPhiD + kPhiD) % kPhiD;
    corners[corner] = {b.Flat(), (dh ? fh : 1 - fh) * (dd ? fd : 1 - fd) * (dp ? fp : 1 - fp)};
  }
  return corners;
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
