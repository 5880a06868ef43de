// The NJR15 log mapping of a BRDF value (docs/architecture.md, "The method in one page"):
//   y = ln((rho * cosw + eps) / (rho_ref + eps)),  rho = ((rho_ref + eps) e^y - eps) / cosw
// where cosw is the clamped cos weight of the bin (merl::CosWeight) and rho_ref the per-bin
// median of the cos-weighted training BRDFs. Negative rho ("no data", or a fit's undershoot)
// is taken as 0: a BRDF is non-negative and ln needs a positive argument.
#pragma once

#include <algorithm>
#include <cmath>

namespace acq {

constexpr double kLogMappingEps = 0.001;

// The mapping of an already cos-weighted, non-negative value.
inline double MapCosWeighted(double rho_cosw, double rho_ref) {
  return std::log((rho_cosw + kLogMappingEps) / (rho_ref + kLogMappingEps));
}

inline double MapBrdf(double rho, double cos_weight, double rho_ref) {
  return MapCosWeighted(std::max(rho, 0.0) * cos_weight, rho_ref);
}

inline double UnmapBrdf(double y, double cos_weight, double rho_ref) {
  return ((rho_ref + kLogMappingEps) * std::exp(y) - kLogMappingEps) / cos_weight;
}

}  // namespace acq
