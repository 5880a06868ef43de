#include "brdf/direction_optimizer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "core/error.h"
#include "core/progress.h"

namespace acq {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// What the optimiser needs to know about every bin, computed once: whether the gantry may take
// its direction, and for a near-field geometry the bin each scored position sees.
class AllowedBins {
 public:
  AllowedBins(const BasisView& basis, const OptimizerOptions& o) {
    // Corner to corner: the sample's extremes are where the near field moves directions most.
    positions_ = o.geometry.Positions(o.geometry.sample_size_mm > 0 ? o.fov_grid : 1, true);
    const std::size_t np = positions_.size();
    allowed_.assign(merl::kBins, 0);
    if (np > 1) position_bins_.assign(merl::kBins * np, 0);
#pragma omp parallel for schedule(static)
    for (std::size_t b = 0; b < merl::kBins; ++b) {
      if (!basis.valid[b]) continue;
      const ArmAngles arms = ArmAnglesFor(merl::BinCentre(merl::BinFromFlat(b)));
      if (!o.constraints.Violation(arms).empty()) continue;
      const DirectionPair far = DirectionsOf(arms);
      bool ok = true;
      for (std::size_t p = 0; p < np && np > 1; ++p) {
        const DirectionPair d = o.geometry.DirectionsAt(far, positions_[p]);
        const std::size_t pb = merl::BinOf(IsotropicAnglesFromDirections(d.in, d.out)).Flat();
        ok = ok && AboveHorizon(d) && basis.valid[pb];
        position_bins_[b * np + p] = std::uint32_t(pb);
      }
      allowed_[b] = ok;
    }
    for (std::size_t b = 0; b < merl::kBins; ++b)
      if (allowed_[b]) list_.push_back(std::uint32_t(b));
  }
  bool Allowed(std::size_t b) const {
    return allowed_[b];
  }
  const std::vector<std::uint32_t>& List() const {
    return list_;
  }
  std::size_t Positions() const {
    return positions_.size();
  }
  std::size_t BinAt(std::size_t b, std::size_t p) const {
    return positions_.size() > 1 ? position_bins_[b * positions_.size() + p] : b;
  }

 private:
  std::vector<Eigen::Vector2d> positions_;
  std::vector<std::uint8_t> allowed_;
  std::vector<std::uint32_t> position_bins_;
  std::vector<std::uint32_t> list_;
};

// Expected squared reconstruction error (see Score::kExpectedError), up to a constant and the
// factor 1/m: sum over i < k of s_i^2 ||(A Qs_all)_i - e_i||^2, A = (Qk^T Qk + eta I)^-1 Qk^T.
double ExpectedError(const BasisView& basis, const std::vector<std::size_t>& bins, int k,
                     double eta) {
  const int all = basis.components;
  const Eigen::MatrixXd qs_all = SampledRows(basis, bins, all);
  const Eigen::MatrixXd qk = qs_all.leftCols(k);
  Eigen::MatrixXd normal = qk.transpose() * qk;
  normal.diagonal().array() += eta;
  Eigen::MatrixXd d = normal.ldlt().solve(qk.transpose() * qs_all);  // k x all
  d.leftCols(k).diagonal().array() -= 1.0;
  double sum = 0;
  for (int i = 0; i < k; ++i)
    sum += basis.singular_values[i] * basis.singular_values[i] * d.row(i).squaredNorm();
  return sum;
}

// A set's score, compared lexicographically: first how far its condition number exceeds the
// cap (0 when under it), then the objective.
struct SetScore {
  double excess = 0;  // log(condition / cap) when over the cap, else 0
  double value = 0;   // condition number or expected error
  double condition = 0;
  bool operator<(const SetScore& o) const {
    return excess != o.excess ? excess < o.excess : value < o.value;
  }
};

class Scorer {
 public:
  Scorer(const BasisView& basis, const AllowedBins& bins, const OptimizerOptions& o)
      : basis_(basis), bins_(bins), options_(o) {}

  // Over the field of view: the worst or mean of each part over positions.
  SetScore Score(const std::vector<std::size_t>& set, int k) const {
    const std::size_t np = bins_.Positions();
    const bool expected = options_.score == acq::Score::kExpectedError;
    SetScore worst, mean;
    std::vector<std::size_t> at(set.size());
    for (std::size_t p = 0; p < np; ++p) {
      for (std::size_t i = 0; i < set.size(); ++i) at[i] = bins_.BinAt(set[i], p);
      SetScore s;
      s.condition = ConditionOfBins(basis_, at, k);
      s.value = expected ? ExpectedError(basis_, at, k, options_.eta) : s.condition;
      // The cap holds at every step of the growth (for the k columns scored then), so the set
      // never drifts where the last steps cannot bring the condition number back.
      if (expected && s.condition > options_.max_condition)
        s.excess = std::log(s.condition / options_.max_condition);
      worst.excess = std::max(worst.excess, s.excess);
      worst.value = std::max(worst.value, s.value);
      worst.condition = std::max(worst.condition, s.condition);
      mean.excess += s.excess / double(np);
      mean.value += s.value / double(np);
      mean.condition += s.condition / double(np);
    }
    return options_.fov_objective == FovObjective::kWorst ? worst : mean;
  }

 private:
  const BasisView& basis_;
  const AllowedBins& bins_;
  const OptimizerOptions& options_;
};

// One bin along each grid axis, both ways; phi_d wraps (0 and 180 degrees are neighbours by
// reciprocity), the others stop at the grid's edge.
std::vector<std::size_t> Neighbours(std::size_t bin) {
  const merl::BinIndex b = merl::BinFromFlat(bin);
  std::vector<std::size_t> out;
  for (int d : {-1, 1}) {
    merl::BinIndex n = b;
    n.theta_h += d;
    if (n.theta_h >= 0 && n.theta_h < merl::kThetaH) out.push_back(n.Flat());
    n = b;
    n.theta_d += d;
    if (n.theta_d >= 0 && n.theta_d < merl::kThetaD) out.push_back(n.Flat());
    n = b;
    n.phi_d = (n.phi_d + d + merl::kPhiD) % merl::kPhiD;
    out.push_back(n.Flat());
  }
  return out;
}

}  // namespace

void OptimizerOptions::Check(const BasisView& basis) const {
  if (n < 1) throw UserError("--n", "must be at least 1");
  if (EffectiveK() < 1 || EffectiveK() > basis.components)
    throw UserError(
        "--k",
        "must be in [1, " + std::to_string(basis.components) + "] (components stored in the basis)",
        "rebuild the basis with more --components or ask for fewer");
  if (EffectiveK() > n)
    throw UserError("--k",
                    std::to_string(EffectiveK()) + " components cannot be determined from " +
                        std::to_string(n) + " directions (k > n)",
                    "use --k <= --n");
  if (candidates < 1) throw UserError("--candidates", "must be at least 1");
  if (fov_grid < 2 && geometry.sample_size_mm > 0)
    throw UserError("--fov-grid", "must be at least 2 for a field-of-view-aware optimisation");
  constraints.Check();
}

OptimizedDirections OptimizeDirections(const BasisView& basis, const OptimizerOptions& options) {
  options.Check(basis);
  const auto start = std::chrono::steady_clock::now();
  const int k_final = options.EffectiveK();
  const AllowedBins allowed(basis, options);
  if (allowed.List().size() < std::size_t(options.n))
    throw UserError("constraints",
                    "only " + std::to_string(allowed.List().size()) +
                        " MERL bins satisfy the constraints, fewer than --n",
                    "relax --max-camera-zenith-deg, --min-separation-deg or the field of view");
  const Scorer scorer(basis, allowed, options);
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<std::size_t> pick(0, allowed.List().size() - 1);

  // 1. The allowed row of largest norm over the k columns scored at the end.
  std::vector<std::size_t> set;
  {
    double best = -1;
    std::size_t arg = 0;
    for (std::uint32_t b : allowed.List()) {
      const float* row = basis.Row(b);
      double norm = 0;
      for (int c = 0; c < k_final; ++c) norm += double(row[c]) * row[c];
      if (norm > best) best = norm, arg = b;
    }
    set.push_back(arg);
  }
  Progress progress("directions: optimising", std::size_t(options.n), options.progress);
  progress.Tick();
  SetScore score = scorer.Score(set, 1);
  for (int j = 2; j <= options.n; ++j) {
    const int k = std::min(j, k_final);
    // 2. Best of many random candidates (drawn first, so the result does not depend on threads).
    std::vector<std::size_t> candidates(std::size_t(options.candidates));
    for (auto& c : candidates) c = allowed.List()[pick(rng)];
    std::vector<SetScore> scores(candidates.size());
#pragma omp parallel for schedule(dynamic, 16)
    for (int c = 0; c < int(candidates.size()); ++c) {
      std::vector<std::size_t> trial = set;
      trial.push_back(candidates[c]);
      scores[c] = scorer.Score(trial, k);
    }
    const auto best = std::min_element(scores.begin(), scores.end()) - scores.begin();
    set.push_back(candidates[best]);
    score = scores[best];
    // 3. Local search along the grid axes while the score falls.
    for (bool improved = true; improved;) {
      improved = false;
      for (std::size_t i = 0; i < set.size(); ++i) {
        const std::vector<std::size_t> moves = Neighbours(set[i]);
        std::vector<SetScore> move_scores(moves.size(), SetScore{kInf, kInf, kInf});
#pragma omp parallel for schedule(static)
        for (int m = 0; m < int(moves.size()); ++m) {
          if (!allowed.Allowed(moves[m]) ||
              std::find(set.begin(), set.end(), moves[m]) != set.end())
            continue;
          std::vector<std::size_t> trial = set;
          trial[i] = moves[m];
          move_scores[m] = scorer.Score(trial, k);
        }
        const auto m =
            std::min_element(move_scores.begin(), move_scores.end()) - move_scores.begin();
        if (move_scores[m].excess < score.excess ||
            (move_scores[m].excess == score.excess &&
             move_scores[m].value < score.value * (1 - 1e-9))) {
          set[i] = moves[m];
          score = move_scores[m];
          improved = true;
        }
      }
    }
    progress.Tick();
  }

  OptimizedDirections out;
  for (std::size_t b : set)
    out.directions.push_back({merl::BinCentre(merl::BinFromFlat(b)), "optimised"});
  out.condition = score.condition;
  out.expected_error = options.score == acq::Score::kExpectedError ? score.value : 0.0;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace acq
