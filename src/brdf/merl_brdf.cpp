#include "brdf/merl_brdf.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "core/colour.h"
#include "core/error.h"

namespace acq {

std::array<double, 3> MerlBrdf::Lookup(const Eigen::Vector3d& in,
                                       const Eigen::Vector3d& out) const {
  const std::size_t bin = merl::BinOf(IsotropicAnglesFromDirections(in, out)).Flat();
  return {Value(0, bin), Value(1, bin), Value(2, bin)};
}

std::array<double, 3> MerlBrdf::LookupInterpolated(const Eigen::Vector3d& in,
                                                   const Eigen::Vector3d& out) const {
  std::array<double, 3> sum = {0, 0, 0};
  double total = 0;
  for (const merl::Corner& corner :
       merl::InterpolationCorners(IsotropicAnglesFromDirections(in, out))) {
    if (corner.weight <= 0 || raw[corner.bin] < 0) continue;  // -1: "no data" (MERL marks all 3)
    for (int c = 0; c < 3; ++c) sum[c] += corner.weight * Value(c, corner.bin);
    total += corner.weight;
  }
  if (total > 0)
    for (double& v : sum) v /= total;
  return sum;
}

MerlBrdf ReadMerlBinary(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw UserError(path, "cannot open MERL .binary file", "check the path");
  std::int32_t dims[3] = {0, 0, 0};
  if (!f.read(reinterpret_cast<char*>(dims), sizeof dims))
    throw UserError(path, "file is shorter than the 12-byte MERL header",
                    "the file is truncated or not a MERL .binary");
  if (dims[0] != merl::kThetaH || dims[1] != merl::kThetaD || dims[2] != merl::kPhiD) {
    throw UserError(path,
                    "MERL header says " + std::to_string(dims[0]) + " x " +
                        std::to_string(dims[1]) + " x " + std::to_string(dims[2]) +
                        " bins, expected 90 x 90 x 180",
                    "only the standard isotropic MERL grid is supported");
  }
  MerlBrdf brdf;
  const std::streamsize want = std::streamsize(brdf.raw.size() * sizeof(double));
  f.read(reinterpret_cast<char*>(brdf.raw.data()), want);
  if (f.gcount() != want) {
    throw UserError(path,
                    "truncated: " + std::to_string(12 + f.gcount()) + " bytes, expected " +
                        std::to_string(12 + want),
                    "re-copy or re-export the file");
  }
  if (f.peek() != std::char_traits<char>::eof())
    throw UserError(path, "has trailing bytes after the 3 x 1458000 doubles",
                    "the file is not a MERL .binary");
  for (std::size_t i = 0; i < brdf.raw.size(); ++i) {
    if (!std::isfinite(brdf.raw[i])) {
      const merl::BinIndex b = merl::BinFromFlat(i % merl::kBins);
      throw UserError(path,
                      std::string("non-finite value in channel ") + "RGB"[i / merl::kBins] +
                          " at bin (theta_h " + std::to_string(b.theta_h) + ", theta_d " +
                          std::to_string(b.theta_d) + ", phi_d " + std::to_string(b.phi_d) + ")",
                      "the file is corrupt; MERL marks missing data with negative values");
    }
  }
  return brdf;
}

void WriteMerlBinary(const MerlBrdf& brdf, const std::string& path) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw UserError(path, "cannot create file", "check the folder exists and is writable");
  const std::int32_t dims[3] = {merl::kThetaH, merl::kThetaD, merl::kPhiD};
  f.write(reinterpret_cast<const char*>(dims), sizeof dims);
  f.write(reinterpret_cast<const char*>(brdf.raw.data()),
          std::streamsize(brdf.raw.size() * sizeof(double)));
  if (!f) throw UserError(path, "write failed", "check free disk space");
}

MerlBrdf LuminanceOf(const MerlBrdf& brdf) {
  MerlBrdf out;
  for (std::size_t bin = 0; bin < merl::kBins; ++bin) {
    double y = 0;
    bool known = true;
    for (int c = 0; c < 3; ++c) {
      const double v = brdf.Value(c, bin);
      known = known && v >= 0;
      y += kRec709Luminance[c] * v;
    }
    if (known)  // unknown bins stay at the table's "no data" (-1)
      for (int c = 0; c < 3; ++c) out.SetValue(c, bin, y);
  }
  return out;
}

}  // namespace acq
