// A tabulated isotropic BRDF on the MERL grid, and MERL's `.binary` file format:
// three little-endian int32 (90, 90, 180), then kBins float64 for R, then G, then B.
//
// Values are kept exactly as stored in the file ("raw"); Value() applies MERL's per-channel
// scale as MERL's own reader does. Keeping the raw numbers makes write -> read and
// read -> write bit-identical, which scaling on load would not be.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/merl_grid.h"

namespace acq {

constexpr std::array<double, 3> kMerlChannelScale = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

struct MerlBrdf {
  std::vector<double> raw = std::vector<double>(3 * merl::kBins, -1.0);  // R, then G, then B

  // BRDF value (1/sr) of a channel at a flat bin index; negative means "no data".
  double Value(int channel, std::size_t bin) const {
    return raw[channel * merl::kBins + bin] * kMerlChannelScale[channel];
  }
  void SetValue(int channel, std::size_t bin, double value) {
    raw[channel * merl::kBins + bin] = value / kMerlChannelScale[channel];
  }
  // MERL's lookup: bin of the directions, then Value. Directions in the surface frame.
  std::array<double, 3> Lookup(const Eigen::Vector3d& in, const Eigen::Vector3d& out) const;
  // Trilinear between the bin centres around the directions (merl::InterpolationCorners; bins
  // without data left out, the others' weights renormalised; zeros if none has data): the
  // tabulated function between its samples, where Lookup is a step at every bin edge (at a
  // narrow highlight a step of 10% and more, docs/colour.md, "The view nearest the highlight").
  std::array<double, 3> LookupInterpolated(const Eigen::Vector3d& in,
                                           const Eigen::Vector3d& out) const;
};

// Throws UserError naming the file on a short file, wrong dimensions or NaN/Inf values.
MerlBrdf ReadMerlBinary(const std::string& path);
void WriteMerlBinary(const MerlBrdf& brdf, const std::string& path);

// What a mono camera records of a colour BRDF: Rec. 709 luminance in all three channels (the
// simulated camera's luminance channel, sim/sample_renderer.h).
MerlBrdf LuminanceOf(const MerlBrdf& brdf);

}  // namespace acq
