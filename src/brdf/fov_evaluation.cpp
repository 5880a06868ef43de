#include "brdf/fov_evaluation.h"

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "brdf/evaluation.h"
#include "brdf/log_mapping.h"

namespace acq {
namespace {

// The directions of each pose's arms seen from the sample centre (the far field).
std::vector<DirectionPair> FarDirections(const std::vector<Direction>& directions) {
  std::vector<DirectionPair> far;
  for (const Direction& d : directions) far.push_back(DirectionsOf(ArmAnglesFor(d.angles)));
  return far;
}

// The bin each direction gives at `position` on the sample (mm, sample frame): the near-field
// version of its arms' directions; none where it falls below the horizon there or into a masked
// bin, so gives no observation.
std::vector<std::optional<std::size_t>> BinsSeenAt(const BasisView& basis,
                                                   const std::vector<DirectionPair>& far,
                                                   const NearFieldGeometry& geometry,
                                                   const Eigen::Vector2d& position) {
  std::vector<std::optional<std::size_t>> bins;
  for (const DirectionPair& arms : far) {
    const DirectionPair d = geometry.DirectionsAt(arms, position);
    const std::size_t bin = merl::BinOf(IsotropicAnglesFromDirections(d.in, d.out)).Flat();
    bins.push_back(AboveHorizon(d) && basis.valid[bin] ? std::optional(bin) : std::nullopt);
  }
  return bins;
}

}  // namespace

HeldOutSet::HeldOutSet(const BasisView& basis, const std::vector<MerlBrdf>& materials)
    : basis_(basis) {
  const merl::GridGeometry& grid = merl::Geometry();
  const int kk = basis.components;
  valid_bins_ = double(grid.valid_bins.size());
  gram_ = Eigen::MatrixXd::Zero(kk, kk);
  for (std::uint32_t b : grid.valid_bins) {
    const Eigen::Map<const Eigen::VectorXf> row(basis.Row(b), kk);
    gram_.selfadjointView<Eigen::Lower>().rankUpdate(row.cast<double>());
  }
  gram_ = gram_.selfadjointView<Eigen::Lower>();
  const int channels = int(3 * materials.size());
  mapped_.assign(channels, std::vector<float>(merl::kBins, 0.0f));
  qt_r_.assign(channels, Eigen::VectorXd::Zero(kk));
  r_r_.assign(channels, 0.0);
#pragma omp parallel for schedule(dynamic)
  for (int ch = 0; ch < channels; ++ch) {
    const MerlBrdf& m = materials[ch / 3];
    for (std::uint32_t b : grid.valid_bins) {
      const double x = MapBrdf(m.Value(ch % 3, b), grid.cos_weight[b], basis.ref[b]);
      mapped_[ch][b] = float(x);
      const double r = x - basis.mean[b];
      qt_r_[ch] += r * Eigen::Map<const Eigen::VectorXf>(basis.Row(b), kk).cast<double>();
      r_r_[ch] += r * r;
    }
  }
}

double HeldOutSet::LogRmse(int ch, const Eigen::VectorXd& c) const {
  const int k = int(c.size());
  const double sq = c.dot(gram_.topLeftCorner(k, k) * c) - 2 * c.dot(qt_r_[ch].head(k)) + r_r_[ch];
  return std::sqrt(std::max(sq, 0.0) / valid_bins_);
}

double HeldOutSet::NoiseGain(const Eigen::MatrixXd& a) const {
  const Eigen::Index k = a.rows();
  return std::sqrt((a.transpose() * gram_.topLeftCorner(k, k) * a).trace() / valid_bins_);
}

FovResult EvaluateOverFov(const HeldOutSet& h, const std::vector<Direction>& directions,
                          const FovEvalOptions& o) {
  const BasisView& basis = h.basis();
  o.ridge.Check(basis);
  const int k = o.ridge.components;
  const std::vector<Eigen::Vector2d> positions = o.geometry.Positions(o.grid);
  const std::vector<DirectionPair> arms = FarDirections(directions);
  const std::vector<std::size_t> centre_bins = BinsOf(directions);

  FovResult result;
  result.positions = int(positions.size());
  result.channel_log_rmse.assign(h.Channels(), 0.0);
  result.channel_worst_log_rmse.assign(h.Channels(), 0.0);
  std::vector<double> conditions(positions.size());
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const int trials = o.noise_sigma > 0 ? o.noise_trials : 1;

  for (std::size_t p = 0; p < positions.size(); ++p) {
    // The bins this position really sees; a direction whose near-field version falls below the
    // horizon at this position gives no observation there.
    std::vector<std::size_t> seen, used_rows;
    const std::vector<std::optional<std::size_t>> bins =
        BinsSeenAt(basis, arms, o.geometry, positions[p]);
    for (std::size_t i = 0; i < bins.size(); ++i) {
      if (!bins[i]) continue;
      seen.push_back(*bins[i]);
      used_rows.push_back(o.ignore_near_field ? centre_bins[i] : *bins[i]);
    }
    const Eigen::MatrixXd qs = SampledRows(basis, used_rows, k);
    const Eigen::VectorXd mus = SampledMean(basis, used_rows);
    conditions[p] = ConditionNumber(qs);
    for (int ch = 0; ch < h.Channels(); ++ch) {
      double sum = 0;
      for (int t = 0; t < trials; ++t) {
        Eigen::VectorXd xs(Eigen::Index(seen.size()));
        for (std::size_t r = 0; r < seen.size(); ++r)
          xs(Eigen::Index(r)) = h.Mapped(ch, seen[r]) + o.noise_sigma * noise(rng);
        sum += h.LogRmse(ch, RidgeSolve(qs, xs - mus, o.ridge.eta));
      }
      const double e = sum / trials;
      result.channel_log_rmse[ch] += e / double(positions.size());
      result.channel_worst_log_rmse[ch] = std::max(result.channel_worst_log_rmse[ch], e);
    }
  }
  result.condition_centre = ConditionOfBins(basis, centre_bins, k);
  result.condition_median = Median(conditions);
  result.condition_worst = *std::max_element(conditions.begin(), conditions.end());

  // Noise gain at the centre: observation noise e ~ N(0, I) moves c by A e, with
  // A = (Qs^T Qs + eta I)^-1 Qs^T, and the grid error by sqrt(tr(A^T G A) / bins).
  const Eigen::MatrixXd qs = SampledRows(basis, centre_bins, k);
  Eigen::MatrixXd normal = qs.transpose() * qs;
  normal.diagonal().array() += o.ridge.eta;
  const Eigen::MatrixXd a = normal.ldlt().solve(qs.transpose());
  result.noise_gain = h.NoiseGain(a);
  return result;
}

std::vector<PositionCondition> ConditionOverSample(const BasisView& basis,
                                                   const std::vector<Direction>& directions,
                                                   const NearFieldGeometry& geometry, int grid,
                                                   int k) {
  const std::vector<DirectionPair> far = FarDirections(directions);
  std::vector<PositionCondition> out;
  for (const Eigen::Vector2d& p : geometry.Positions(grid, /*to_edges=*/true)) {
    PositionCondition c{p, 0, {}};
    std::vector<std::size_t> seen;
    const std::vector<std::optional<std::size_t>> bins = BinsSeenAt(basis, far, geometry, p);
    for (std::size_t i = 0; i < bins.size(); ++i) {
      if (bins[i])
        seen.push_back(*bins[i]);
      else
        c.lost.push_back(int(i));
    }
    c.condition = ConditionOfBins(basis, seen, k);  // infinite with fewer rows than k
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace acq
