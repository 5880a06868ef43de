#include "brdf/basis_rows.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "brdf/log_mapping.h"
#include "core/angles.h"
#include "core/merl_grid.h"

namespace acq {

const char* RowLookupName(RowLookup lookup) {
  return lookup == RowLookup::kNearest ? "nearest" : "interpolated";
}

std::optional<RowLookup> ParseRowLookup(const std::string& name) {
  for (RowLookup l : {RowLookup::kNearest, RowLookup::kInterpolated})
    if (name == RowLookupName(l)) return l;
  return std::nullopt;
}

bool SampleBasis(const BasisView& basis, const Eigen::Vector3d& in, const Eigen::Vector3d& out,
                 int k, RowLookup lookup, float* row, BasisSample* sample) {
  if (!(in.z() > 0 && out.z() > 0)) return false;
  return SampleBasisAt(basis, IsotropicAnglesFromDirections(in, out), merl::CosWeight({in, out}), k,
                       lookup, row, sample);
}

bool SampleBasisAt(const BasisView& basis, const RusinkiewiczAngles& a, double cos_weight, int k,
                   RowLookup lookup, float* row, BasisSample* sample) {
  sample->cos_weight = float(cos_weight);
  if (lookup == RowLookup::kNearest) {
    const std::size_t bin = merl::BinOf(a).Flat();
    if (!basis.valid[bin]) return false;
    const float* q = basis.Row(bin);
    for (int c = 0; c < k; ++c) row[c] = q[c];
    sample->mean = basis.mean[bin];
    sample->ref = basis.ref[bin];
    return true;
  }
  for (int c = 0; c < k; ++c) row[c] = 0;
  double total = 0, mean = 0, ref = 0;
  for (const merl::Corner& corner : merl::InterpolationCorners(a)) {
    const double w = corner.weight;
    if (w <= 0 || !basis.valid[corner.bin]) continue;
    const float* q = basis.Row(corner.bin);
    for (int c = 0; c < k; ++c) row[c] += float(w) * q[c];
    mean += w * basis.mean[corner.bin];
    ref += w * basis.ref[corner.bin];
    total += w;
  }
  if (total <= 0) return false;
  const float inv = float(1.0 / total);
  for (int c = 0; c < k; ++c) row[c] *= inv;
  sample->mean = float(mean / total);
  sample->ref = float(ref / total);
  return true;
}

std::array<double, 3> BrdfFromCoefficients(const BasisView& basis, const float* coefficients, int k,
                                           const Eigen::Vector3d& in, const Eigen::Vector3d& out,
                                           RowLookup lookup) {
  std::array<double, 3> rgb = {0, 0, 0};
  float row[256];
  if (k > 256) throw std::logic_error("BrdfFromCoefficients: k > 256");
  BasisSample s;
  if (!SampleBasis(basis, in, out, k, lookup, row, &s)) return rgb;
  for (int c = 0; c < 3; ++c) {
    double x = s.mean;
    for (int j = 0; j < k; ++j) x += double(row[j]) * coefficients[c * k + j];
    rgb[c] = std::max(UnmapBrdf(x, s.cos_weight, s.ref), 0.0);
  }
  return rgb;
}

}  // namespace acq
