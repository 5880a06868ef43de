#include "brdf/evaluation.h"

#include <algorithm>
#include <cmath>

#include "brdf/log_mapping.h"

namespace acq {

std::array<ChannelError, 3> EvaluateHomogeneous(const BasisView& basis, const MerlBrdf& truth,
                                                const std::vector<std::size_t>& bins,
                                                const RidgeOptions& options,
                                                MerlBrdf* reconstruction) {
  options.Check(basis);
  const int k = options.components;
  const merl::GridGeometry& grid = merl::Geometry();
  const Eigen::MatrixXd qs = SampledRows(basis, bins, k);
  const Eigen::VectorXd mus = SampledMean(basis, bins);
  const double condition = ConditionNumber(qs);
  std::array<ChannelError, 3> result;
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd xs(Eigen::Index(bins.size()));
    for (std::size_t r = 0; r < bins.size(); ++r) {
      const std::size_t b = bins[r];
      xs(Eigen::Index(r)) = MapBrdf(truth.Value(c, b), grid.cos_weight[b], basis.ref[b]);
    }
    const Eigen::VectorXd coeff = RidgeSolve(qs, xs - mus, options.eta);
    const Eigen::VectorXf coeff_f = coeff.cast<float>();
    double sq_log = 0, sq_diff = 0, sq_truth = 0;
    for (const std::uint32_t b : grid.valid_bins) {
      const float* row = basis.Row(b);
      double x = basis.mean[b];
      for (int j = 0; j < k; ++j) x += double(row[j]) * coeff_f(j);
      const double cosw = grid.cos_weight[b];
      const double rho_true = std::max(truth.Value(c, b), 0.0);
      const double rho_rec = std::max(UnmapBrdf(x, cosw, basis.ref[b]), 0.0);
      const double d = x - MapBrdf(rho_true, cosw, basis.ref[b]);
      sq_log += d * d;
      sq_diff += (rho_rec - rho_true) * (rho_rec - rho_true) * cosw * cosw;
      sq_truth += rho_true * rho_true * cosw * cosw;
      if (reconstruction) reconstruction->SetValue(c, b, rho_rec);
    }
    result[c].log_rmse = std::sqrt(sq_log / double(grid.valid_bins.size()));
    result[c].relative_rmse = sq_truth > 0 ? std::sqrt(sq_diff / sq_truth) : 0.0;
    result[c].condition = condition;
  }
  return result;
}

double MedianInPlace(double* begin, double* end) {
  if (begin == end) return std::nan("");
  const std::ptrdiff_t n = end - begin;
  double* middle = begin + n / 2;
  std::nth_element(begin, middle, end);
  if (n % 2) return *middle;
  return 0.5 * (*std::max_element(begin, middle) + *middle);  // the two middle values
}

double Median(std::vector<double> values) {
  return MedianInPlace(values.data(), values.data() + values.size());
}

}  // namespace acq
