// Held-out reconstruction over a field of view (Yu et al. Sec. 3.3, Fig. 4): positions spread
// over a flat sample, each seeing its own true light and view directions for the arms of each
// direction (the near-field effect), each reconstructed from its own observations with its own
// rows of the basis, and scored over the whole grid.
//
// The log-space error over all valid bins is computed in closed form: with r = x_true - mu,
//   ||Q_k c - r||^2 = c^T (Q_k^T Q_k) c - 2 c^T (Q_k^T r) + r^T r,
// where Q^T Q, Q^T r and r^T r are computed once per basis and material. Exact (up to rounding)
// and O(k^2) per position instead of O(bins x k).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "brdf/directions.h"
#include "brdf/merl_brdf.h"
#include "brdf/reconstruct.h"
#include "core/gantry_geometry.h"

namespace acq {

struct FovEvalOptions {
  RidgeOptions ridge;
  NearFieldGeometry geometry;  // sample_size_mm = 0: the centre only
  int grid = 10;               // grid x grid positions (the paper uses 100)
  // Reconstruct every position with the centre's rows (what ignoring the near field does).
  bool ignore_near_field = false;
  double noise_sigma = 0;  // Gaussian noise added to the mapped observations (~relative noise)
  int noise_trials = 8;
  std::uint64_t seed = 1;
};

// The held-out materials, prepared for the closed form.
class HeldOutSet {
 public:
  HeldOutSet(const BasisView& basis, const std::vector<MerlBrdf>& materials);
  int Channels() const { return int(mapped_.size()); }
  const BasisView& basis() const { return basis_; }
  // The mapped true value of a channel at a bin (what a noiseless observation there reads).
  double Mapped(int channel, std::size_t bin) const { return mapped_[channel][bin]; }
  // Log-space RMSE over all valid bins of the reconstruction Q_k c + mu of a channel.
  double LogRmse(int channel, const Eigen::VectorXd& c) const;
  // RMS grid error per unit of observation noise for x = Q_k A e + mu, e ~ N(0, I).
  double NoiseGain(const Eigen::MatrixXd& a) const;

 private:
  BasisView basis_;       // a view (pointers) is held by value; the basis must outlive this
  Eigen::MatrixXd gram_;  // Q^T Q over valid bins, all stored components
  std::vector<std::vector<float>> mapped_;  // per channel: mapped truth at every bin
  std::vector<Eigen::VectorXd> qt_r_;       // per channel: Q^T (x - mu)
  std::vector<double> r_r_;                 // per channel: (x - mu)^T (x - mu)
  double valid_bins_ = 0;
};

struct FovResult {
  std::vector<double> channel_log_rmse;        // per channel, mean over positions
  std::vector<double> channel_worst_log_rmse;  // per channel, worst position
  double condition_centre = 0, condition_median = 0, condition_worst = 0;
  // RMS log-space error over the grid per unit of observation noise, at the centre: how much
  // noise the reconstruction amplifies (< 1 averages noise down, > 1 amplifies it).
  double noise_gain = 0;
  int positions = 0;
};

FovResult EvaluateOverFov(const HeldOutSet& held_out, const std::vector<Direction>& directions,
                          const FovEvalOptions& options);

// Where on the sample a set of directions holds up (issue 17): at each of grid x grid positions
// from corner to corner, the condition number of the k rows it sees (infinite with fewer rows
// than k) and the directions it loses (indices into `directions`).
struct PositionCondition {
  Eigen::Vector2d position_mm;
  double condition = 0;
  std::vector<int> lost;
};
std::vector<PositionCondition> ConditionOverSample(const BasisView& basis,
                                                   const std::vector<Direction>& directions,
                                                   const NearFieldGeometry& geometry, int grid,
                                                   int k);

}  // namespace acq
