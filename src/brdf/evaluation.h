// Homogeneous reconstruction of a known material from its values at a direction set, scored
// over every valid bin (the NJR15 / Yu et al. simulation, centre of the sample only).
#pragma once

#include <array>
#include <vector>

#include "brdf/merl_brdf.h"
#include "brdf/reconstruct.h"

namespace acq {

struct ChannelError {
  double log_rmse = 0;       // RMSE of the log-mapped BRDF over valid bins
  double relative_rmse = 0;  // ||rho_rec cosw - rho cosw|| / ||rho cosw|| over valid bins
  double condition = 0;      // condition number of the sampled rows used
};

// Reconstructs each channel of `truth` from its values at `bins`. When `reconstruction` is
// given it receives the reconstructed BRDF (masked bins -1, values clamped to >= 0).
std::array<ChannelError, 3> EvaluateHomogeneous(const BasisView& basis, const MerlBrdf& truth,
                                                const std::vector<std::size_t>& bins,
                                                const RidgeOptions& options,
                                                MerlBrdf* reconstruction = nullptr);

double Median(std::vector<double> values);
// The median of [begin, end), reordering it (no copy: for the many small medians of
// colour_outliers.cpp); NaN when empty.
double MedianInPlace(double* begin, double* end);

}  // namespace acq
