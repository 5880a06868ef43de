// The MERL BRDF grid (Matusik et al. 2003), exactly as docs/architecture.md states it:
// 90 x 90 x 180 bins over (theta_h, theta_d, phi_d); theta_h binned as
// floor(sqrt(theta_h / (pi/2)) * 90), theta_d as floor(theta_d / (pi/2) * 90), and phi_d folded
// into [0, pi) by reciprocity and binned as floor(phi_d / pi * 180), every index clamped to the
// grid as MERL's own reader does. Flat index: phi_d + 180 * theta_d + 180 * 90 * theta_h.
// One deliberate difference: a value within 1e-9 of a bin below its edge counts as on the edge
// (rounding from vector round trips must not move a direction like theta_d = 30 deg to bin 29).
//
// Tabulation positions ("bin centres") are the midpoints of each bin in its binning variable:
// theta_h = ((i + 0.5) / 90)^2 * pi/2, theta_d = (j + 0.5) * pi/180, phi_d = (k + 0.5) * pi/180.
// Midpoints make BinOf(BinCentre(b)) == b exact for every bin, which edge positions are not.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/rusinkiewicz.h"

namespace acq::merl {

constexpr int kThetaH = 90;
constexpr int kThetaD = 90;
constexpr int kPhiD = 180;
constexpr std::size_t kBins = std::size_t{kThetaH} * kThetaD * kPhiD;  // 1,458,000

struct BinIndex {
  int theta_h = 0, theta_d = 0, phi_d = 0;
  std::size_t Flat() const {
    return std::size_t(phi_d) + std::size_t(kPhiD) * theta_d +
           std::size_t(kPhiD) * kThetaD * theta_h;
  }
  bool operator==(const BinIndex&) const = default;
};

// A value this close below a bin edge (in index units) counts as on the edge: angles that went
// through a direction-vector round trip come back 1e-15 short of values like 30 degrees that
// sit exactly on an edge, and must land where the angle says. At most 1e-9 of a bin differs
// from MERL's reader.
constexpr double kEdgeSlack = 1e-9;

int ThetaHIndex(double theta_h);
int ThetaDIndex(double theta_d);
int PhiDIndex(double phi_d);  // accepts any phi_d in [-pi, pi]; folds by reciprocity
BinIndex BinOf(const RusinkiewiczAngles& a);
BinIndex BinFromFlat(std::size_t flat);

// Position at which a bin is tabulated (phi_h = 0).
RusinkiewiczAngles BinCentre(const BinIndex& b);

// Trilinear interpolation between bin centres: the 8 centres around the angles and their
// weights (summing to 1), in the grid's index coordinates (theta_h sqrt-spaced as binned;
// theta_h and theta_d held constant beyond the first and last centre; phi_d periodic over
// [0, pi) by reciprocity). Callers skip corners without data and renormalise.
struct Corner {
  std::size_t bin = 0;  // flat index
  double weight = 0;
};
std::array<Corner, 8> InterpolationCorners(const RusinkiewiczAngles& a);

// cos(theta_i) * cos(theta_o) clamped to [kCosWeightMin, 1]: the NJR15 cos weight.
constexpr double kCosWeightMin = 0.01;
double CosWeight(const DirectionPair& d);

// Per-bin geometry at the bin centres: which bins have both directions above the horizon
// (the others are masked out everywhere), and their cos weight.
struct GridGeometry {
  std::vector<std::uint8_t> valid;        // kBins entries, 1 = above the horizon
  std::vector<float> cos_weight;          // kBins entries, 0 where invalid
  std::vector<std::uint32_t> valid_bins;  // flat indices of the valid bins, ascending
};
const GridGeometry& Geometry();  // computed once, thread-safe

}  // namespace acq::merl
