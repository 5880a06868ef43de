#include "brdf/normal_search.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "brdf/evaluation.h"
#include "brdf/log_mapping.h"
#include "brdf/pixel_rows.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/facet_frame.h"

namespace acq {
namespace {

// A candidate may use at most this many views fewer than the sample's normal does: a residual
// over fewer views is not comparable, and dropping the views that disagree is not a fit.
constexpr int kViewsItMayLose = 2;

struct Candidate {
  Eigen::Vector2f slope;
  double score = std::numeric_limits<double>::infinity();
  int views = 0;  // the solve's observations
  // Criterion kCentre: the group whose centre scored it, and that centre's RMS misfit.
  int group = -1;
  double misfit = std::numeric_limits<double>::infinity();
  // A mixed pixel (NormalSearchOptions::mixed_pixels): the other group whose centre's BRDF is
  // mixed with the first's (the first's share at least half); -1 for one centre.
  int second = -1;
  float share = 1;  // the first group's share of a mixture
};

// A view that a candidate facet turns away from (light behind it, or the facet hidden from the
// camera) is not a view the candidate may drop: the facet would be dark there (as the renderer
// makes it) and the pixel was seen lit. Scored as a prediction of zero, the view costs the
// candidate its mapped observation's height above the mapping's floor. Otherwise tilting away
// from the one view a material's centre fits worst (a grazing light) lowers the RMS misfit.
// Computed once a chunk (pixels [first, first + count)), charged for every candidate.
struct DarkViews {
  int first = 0;
  std::vector<double> cost;  // per pixel and view: squared mapped residual of zero, 3 channels;
                             // NaN: not seen
  DarkViews(const BasisView& basis, const PixelObservations& obs, int first, int count,
            RowLookup lookup)
      : first(first),
        cost(std::size_t(count) * obs.views, std::numeric_limits<double>::quiet_NaN()) {
#pragma omp parallel
    {
      ViewRows rows;
#pragma omp for schedule(dynamic, 64)
      for (int p = 0; p < count; ++p) {
        rows.SampleInLanes(basis, obs, first + p, 1, lookup);
        for (int v = 0; v < obs.views; ++v) {
          const float* rgb = &obs.rgb[3 * obs.At(first + p, v)];
          if (!(rows.ok[v] && std::isfinite(rgb[0]) && std::isfinite(rgb[1]) &&
                std::isfinite(rgb[2])))
            continue;
          const BasisSample& b = rows.samples[v];
          double sum = 0;
          for (int c = 0; c < 3; ++c)
            sum +=
                std::pow(MapBrdf(rgb[c], b.cos_weight, b.ref) - MapBrdf(0, b.cos_weight, b.ref), 2);
          cost[std::size_t(p) * obs.views + v] = sum;
        }
      }
    }
  }
  // The views a candidate facet `n` of `pixel` turns away from: their summed cost and count.
  struct TurnedAway {
    double cost = 0;
    int views = 0;
  };
  TurnedAway Of(const Eigen::Vector3f& n, const PixelObservations& obs, int pixel) const {
    const Eigen::Matrix3f r = FacetFromSample(n);
    const double* pixel_cost = &cost[std::size_t(pixel - first) * obs.views];
    TurnedAway t;
    for (int v = 0; v < obs.views; ++v) {
      const std::size_t i = obs.At(pixel, v);
      if (std::isnan(pixel_cost[v])) continue;
      if ((r * obs.light[i]).z() > 0 && (r * obs.camera[i]).z() > 0) continue;
      t.cost += pixel_cost[v];
      ++t.views;
    }
    return t;
  }
  // `misfit` (RMS over 3 x `views` values) with the views turned away added.
  static void Charge(const TurnedAway& t, double* misfit, int* views) {
    if (t.views == 0) return;
    const double sum = *misfit * *misfit * 3.0 * *views + t.cost;
    *views += t.views;
    *misfit = std::sqrt(sum / (3.0 * *views));
  }
};

// Scores candidates[p] (one list per pixel of the chunk [first, first + count)) with one batch
// of the per-pixel solver.
void ScoreCandidates(const BasisView& basis, const PixelObservations& obs, int first, int count,
                     const std::vector<std::vector<Candidate>>& lists,
                     const PixelSolveOptions& solve, const NormalSearchOptions& o,
                     const DarkViews& dark, std::vector<std::vector<Candidate>>* scored) {
  int total = 0;
  for (const auto& l : lists) total += int(l.size());
  PixelObservations batch;
  batch.Resize(total, obs.views);
  std::vector<std::pair<int, int>> owner(total);
  int at = 0;
  for (int p = 0; p < count; ++p)
    for (std::size_t c = 0; c < lists[p].size(); ++c, ++at) {
      owner[at] = {p, int(c)};
      const Eigen::Vector2f& s = lists[p][c].slope;
      ToFacetFrame(NormalOfSlope(s.x(), s.y()), std::max(o.min_cos, o.score_min_cos), obs,
                   first + p, &batch, at);
    }
  PixelSolveOptions search = solve;
  search.components = o.components;
  search.eta = o.eta;
  search.row_tile = 1;
  search.residual = o.criterion == NormalCriterion::kHeldOut ? ResidualKind::kLeaveOneViewOut
                                                             : ResidualKind::kFit;
  PixelSolution solution;
  solution.Resize(total, o.components);
  SolvePixels(basis, batch, search, &solution);
  *scored = lists;
  for (int i = 0; i < total; ++i) {
    const auto [p, c] = owner[i];
    Candidate& cand = (*scored)[p][c];
    cand.views = solution.observations[i];
    // Not valid (too few views, too poorly conditioned, not finite): no score.
    if (!solution.valid[i]) continue;
    cand.misfit = solution.residual[i];
    DarkViews::Charge(dark.Of(NormalOfSlope(cand.slope.x(), cand.slope.y()), obs, first + p),
                      &cand.misfit, &cand.views);
    cand.score = cand.misfit + o.prior * double(cand.slope.squaredNorm());
  }
}

// Pixels [first, first + count) of `obs`, copied (to solve apart, or to turn them in place).
PixelObservations CopyPixels(const PixelObservations& obs, int first, int count) {
  PixelObservations out;
  out.Resize(count, obs.views);
  const std::size_t from = obs.At(first, 0), to = obs.At(first + count, 0);
  std::copy(obs.light.begin() + from, obs.light.begin() + to, out.light.begin());
  std::copy(obs.camera.begin() + from, obs.camera.begin() + to, out.camera.begin());
  std::copy(obs.rgb.begin() + 3 * from, obs.rgb.begin() + 3 * to, out.rgb.begin());
  return out;
}

// The information criterion of NormalSearchOptions::evidence: does the best candidate's misfit
// (RMS over 3 x views residuals) improve on the sample's normal's by enough for two parameters?
bool TiltEarnsItsKeep(const Candidate& flat, const Candidate& best, double evidence) {
  if (best.slope.isZero()) return true;          // nothing to earn
  if (!std::isfinite(flat.misfit)) return true;  // the sample's normal was not usable at all
  if (!(best.misfit > 0)) return true;
  const double n = 3.0 * best.views;
  return n * 2 * std::log(flat.misfit / best.misfit) > evidence * 2 * std::log(n);
}

// Criterion kCentre: each pixel's candidate groups (the kCentreGroups nearest to its flat
// independent solve in the model's feature space).
constexpr int kCentreGroups = 3;
// FitNormalReference: a group is a larger group's relief (or an edge of it) when the larger
// group's centre, tilted, explains its pixels better than its own centre does flat: the ratio
// of their misfits under 1. Measured through acqd (docs/reconstruction.md, "The reference's
// groups are materials"): the groups taken out lay at 0.14-0.96, the materials kept at 4.9 and
// more, a second group of white paint on a flat card (by its size) at 1.43.
constexpr double kReliefRatio = 1;
std::vector<std::vector<int>> NearestGroups(const BasisView& basis, const PixelObservations& obs,
                                            int first, int count, const PooledModel& model,
                                            const PixelSolveOptions& solve) {
  // The pixels solved as the model's own were when it was clustered: the map's k, alone.
  const PixelObservations chunk = CopyPixels(obs, first, count);
  PixelSolveOptions flat = solve;
  flat.row_tile = 1;
  flat.residual = ResidualKind::kFit;
  PixelSolution solution;
  solution.Resize(count, flat.components);
  SolvePixels(basis, chunk, flat, &solution);
  std::vector<std::vector<int>> nearest(count);
  std::vector<double> feature(3 * model.features);
  for (int p = 0; p < count; ++p) {
    model.Feature(&solution.coefficients[std::size_t(p) * 3 * flat.components], flat.components,
                  feature.data());
    nearest[p] = model.NearestGroups(feature, kCentreGroups);
  }
  return nearest;
}

// The shares of a pair of centres tried for a mixed pixel (NormalSearchOptions::mixed_pixels).
constexpr std::array<float, 3> kMixedShares = {0.25f, 0.5f, 0.75f};

// SeenDarkWhereLit's thresholds. A view squarely in front of a facet: light and camera within
// 80 degrees of its normal, so that an estimate a few degrees off does not turn the view away.
// Dark: a tenth of the prediction in every channel, far beyond the noise (10% at most in the
// study) and a mixed pixel's share (a quarter). Lit: a quarter of the explanation's median, so
// that a glossy ink's dark off-specular views are not read as shadows.
constexpr float kFacingCos = 0.17f;
constexpr float kDarkFraction = 0.1f;
constexpr double kLitFraction = 0.25;

// One pixel's candidates scored by the best of its groups' centres (or two of them mixed),
// coefficients held.
struct CentreScorer {
  CentreScorer(const BasisView& basis, const PooledModel& model, RowLookup lookup,
               const DarkViews& dark)
      : basis(basis), model(model), lookup(lookup), dark(dark) {
    CopyCentres();
  }
  const BasisView& basis;
  const PooledModel& model;
  RowLookup lookup;
  PixelObservations one;
  ViewRows rows;
  std::vector<int> used;  // views usable at the candidate
  Eigen::ArrayXd y;       // their mapped observations less the mean, 3 a view
  const DarkViews& dark;  // the chunk's views as a facet turned away from them scores them

  // The observations in `one`, mapped, with the basis sampled at kc components.
  // The mapping's logarithms run on Eigen arrays (SIMD lanes): log_cosw and log_ref are what
  // the mixtures (mixed_pixels) reuse.
  void Prepare(int kc) {
    rows.SampleInLanes(basis, one, 0, kc, lookup);
    used.clear();
    for (int v = 0; v < one.views; ++v) {
      const float* rgb = &one.rgb[3 * v];
      if (rows.ok[v] && std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2]))
        used.push_back(v);
    }
    const Eigen::Index n = Eigen::Index(3 * used.size());
    log_cosw.resize(n);  // the values first, their logarithms below
    log_ref.resize(n);
    y.resize(n);
    for (std::size_t i = 0; i < used.size(); ++i) {
      const BasisSample& s = rows.samples[used[i]];
      for (int ch = 0; ch < 3; ++ch) {
        const Eigen::Index j = Eigen::Index(3 * i + ch);
        log_cosw[j] = std::max(double(one.rgb[3 * used[i] + ch]), 0.0) * s.cos_weight;
        log_ref[j] = s.ref;
        y[j] = s.mean;
      }
    }
    // MapBrdf, less the mean: ln((rho cos_weight + eps) / (rho_ref + eps)) - mu.
    log_cosw = (log_cosw + kLogMappingEps).log();
    log_ref = (log_ref + kLogMappingEps).log();
    y = log_cosw - log_ref - y;
  }
  Eigen::ArrayXd log_cosw;  // per used value: ln(rho cos_weight + eps) of the observation
  Eigen::ArrayXd log_ref;   // ln(rho_ref + eps) of its bin

  // The RMS log-space misfit of group g's centre (its k_c components; zero past them), over the
  // used views but the `trim` worst-explained (TrimmedRms).
  double Misfit(int g, int trim) {
    const int kc = model.groups[g].centre_components;
    predicted.noalias() = rows.rows.leftCols(kc) * centres[g].topRows(kc);
    view_misfit.assign(used.size(), 0.0);
    for (std::size_t i = 0; i < used.size(); ++i)
      for (int ch = 0; ch < 3; ++ch)
        view_misfit[i] += std::pow(predicted(used[i], ch) - y[3 * i + ch], 2);
    Weigh(g, g);
    return TrimmedRms(trim);
  }
  // Each used view's squared misfit times its weight (PooledGroup::view_weight; a mixture of
  // groups a and b: the mean of theirs).
  void Weigh(int a, int b) {
    const std::vector<double>& wa = model.groups[a].view_weight;
    const std::vector<double>& wb = model.groups[b].view_weight;
    if (wa.empty() && wb.empty()) return;
    for (std::size_t i = 0; i < used.size(); ++i) {
      const std::size_t v = std::size_t(used[i]);
      const double w = 0.5 * ((v < wa.size() ? wa[v] : 1.0) + (v < wb.size() ? wb[v] : 1.0));
      view_misfit[i] *= w;
    }
  }
  // Each used view's squared misfit summed over its channels (Misfit's, MixedMisfit's).
  std::vector<double> view_misfit;
  // How many views a score keeps: all used but `trim` (none left out of fewer than 2).
  int KeptViews(int trim) const {
    const int n = int(used.size());
    return n - std::min(trim, std::max(n - 1, 0));
  }
  // The RMS over 3 x KeptViews residuals of view_misfit, its `trim` largest left out.
  double TrimmedRms(int trim) {
    const int kept = KeptViews(trim);
    if (kept <= 0) return std::numeric_limits<double>::infinity();
    const auto worst = view_misfit.begin() + (std::ptrdiff_t(view_misfit.size()) - kept);
    if (worst != view_misfit.begin())
      std::nth_element(view_misfit.begin(), worst, view_misfit.end(), std::greater<double>());
    double sum = 0;
    for (auto it = worst; it != view_misfit.end(); ++it) sum += *it;
    return std::sqrt(sum / (3.0 * kept));
  }
  // The groups' centres as K x 3 matrices (a channel a column), for Misfit's product.
  void CopyCentres() {
    centres.resize(model.groups.size());
    for (std::size_t g = 0; g < model.groups.size(); ++g) {
      centres[g].resize(model.components, 3);
      for (int ch = 0; ch < 3; ++ch)
        for (int j = 0; j < model.components; ++j)
          centres[g](j, ch) = model.groups[g].centre[std::size_t(ch) * model.components + j];
    }
  }
  std::vector<Eigen::MatrixXd> centres;
  Eigen::MatrixXd predicted;  // views x 3

  // A mixed pixel's terms are single precision: their exp and log run in SIMD lanes twice as
  // wide as double's, which keeps the pairs' price to about 13% of the search's; the misfits
  // they compare differ by far more than float's rounding.
  Eigen::ArrayXf observed;  // log_cosw
  Eigen::ArrayXf mapped;    // KeepBrdf's: the centre's ln(rho cos_weight + eps)
  std::array<Eigen::ArrayXf, kCentreGroups> brdf_cosw;  // per slot of the pixel's groups

  // The cos-weighted BRDF at the used views (UnmapBrdf times the cos weight) of the centre
  // whose prediction `predicted` holds (Misfit's last), into slot `slot`.
  void KeepBrdf(int slot) {
    mapped.resize(y.size());  // no allocation once the size is the views'
    for (std::size_t i = 0; i < used.size(); ++i)
      for (int ch = 0; ch < 3; ++ch)
        mapped[Eigen::Index(3 * i + ch)] =
            float(predicted(used[i], ch) + rows.samples[used[i]].mean + log_ref[3 * i + ch]);
    brdf_cosw[slot].resize(mapped.size());
    brdf_cosw[slot] = (mapped.exp() - float(kLogMappingEps)).max(0.0f);
  }
  // The RMS log-space misfit of slots a and b mixed, `share` of a's (MapBrdf of the mixture),
  // over the used views but the `trim` worst-explained; the logarithms in one expression.
  double MixedMisfit(int a, int b, int group_a, int group_b, float share, int trim) {
    mixed_square =
        ((share * brdf_cosw[a] + (1 - share) * brdf_cosw[b] + float(kLogMappingEps)).log() -
         observed)
            .square();
    view_misfit.resize(used.size());
    for (std::size_t i = 0; i < used.size(); ++i)
      view_misfit[i] = double(mixed_square.segment(Eigen::Index(3 * i), 3).sum());
    Weigh(group_a, group_b);
    return TrimmedRms(trim);
  }
  Eigen::ArrayXf mixed_square;  // MixedMisfit's per residual
  void Score(const PixelObservations& obs, int pixel, const std::vector<int>& groups,
             const NormalSearchOptions& o, int min_views, std::vector<Candidate>* candidates) {
    one.Resize(1, obs.views);
    int kc = 0;
    for (int g : groups) kc = std::max(kc, model.groups[g].centre_components);
    for (Candidate& cand : *candidates) {
      const Eigen::Vector3f n = NormalOfSlope(cand.slope.x(), cand.slope.y());
      ToFacetFrame(n, std::max(o.min_cos, o.score_min_cos), obs, pixel, &one, 0);
      Prepare(kc);
      if (int(used.size()) < min_views) continue;
      const DarkViews::TurnedAway turned = dark.Of(n, obs, pixel);
      const auto consider = [&](double misfit, int g, int second, float share) {
        int views = KeptViews(o.trimmed_views);
        DarkViews::Charge(turned, &misfit, &views);
        const double score = misfit + o.prior * double(cand.slope.squaredNorm());
        if (score < cand.score) cand = {cand.slope, score, views, g, misfit, second, share};
      };
      const bool mixtures = o.mixed_pixels && groups.size() >= 2;
      if (mixtures) observed = log_cosw.cast<float>();
      for (std::size_t a = 0; a < groups.size(); ++a) {
        consider(Misfit(groups[a], o.trimmed_views), groups[a], -1, 1);
        if (mixtures) KeepBrdf(int(a));
      }
      if (!mixtures) continue;
      for (std::size_t a = 0; a < groups.size(); ++a)
        for (std::size_t b = a + 1; b < groups.size(); ++b)
          for (float share : kMixedShares) {
            const bool a_first = share >= 0.5f;
            consider(MixedMisfit(int(a), int(b), groups[a], groups[b], share, o.trimmed_views),
                     a_first ? groups[a] : groups[b], a_first ? groups[b] : groups[a],
                     a_first ? share : 1 - share);
          }
    }
  }
  // How many views the facet of `best` faces squarely (light and camera both at a cosine of
  // kFacingCos or more) were seen dark: every channel under kDarkFraction of what its
  // explanation (its centre, or two centres mixed) predicts there, where that prediction is
  // lit (at least kLitFraction of the explanation's median over those views). The renderer
  // makes a facet dark only where it turns away from a view, so such a view says the true facet
  // turns away where the estimate faces: relief steeper than the search's cone.
  int SeenDarkWhereLit(const PixelObservations& obs, int pixel, const Candidate& best,
                       const NormalSearchOptions& o) {
    one.Resize(1, obs.views);
    ToFacetFrame(NormalOfSlope(best.slope.x(), best.slope.y()),
                 std::max(o.min_cos, o.score_min_cos), obs, pixel, &one, 0);
    int kc = model.groups[best.group].centre_components;
    if (best.second >= 0) kc = std::max(kc, model.groups[best.second].centre_components);
    Prepare(kc);
    Misfit(best.group, 0);  // for `predicted`
    KeepBrdf(0);
    Eigen::ArrayXf lit = brdf_cosw[0];  // the explanation's cos-weighted BRDF at the used views
    if (best.second >= 0) {
      Misfit(best.second, 0);
      KeepBrdf(1);
      lit = best.share * brdf_cosw[0] + (1 - best.share) * brdf_cosw[1];
    }
    std::vector<double> facing_lit;
    std::vector<std::size_t> facing;
    for (std::size_t i = 0; i < used.size(); ++i) {
      const int v = used[i];
      if (std::min(one.light[v].z(), one.camera[v].z()) < kFacingCos) continue;
      facing.push_back(i);
      facing_lit.push_back(lit.segment(Eigen::Index(3 * i), 3).sum());
    }
    if (facing.empty()) return 0;
    std::vector<double> sorted = facing_lit;
    const double median = MedianInPlace(sorted.data(), sorted.data() + sorted.size());
    int dark = 0;
    for (std::size_t f = 0; f < facing.size(); ++f) {
      if (!(facing_lit[f] >= kLitFraction * median)) continue;
      const std::size_t i = facing[f];
      const double cos_weight = rows.samples[used[i]].cos_weight;
      bool all_dark = true;
      for (int ch = 0; ch < 3; ++ch)
        all_dark = all_dark && one.rgb[3 * used[i] + ch] * cos_weight <
                                   kDarkFraction * lit[Eigen::Index(3 * i + ch)];
      dark += all_dark;
    }
    return dark;
  }
};

// The centre scorer over a chunk's candidate lists (OpenMP across pixels).
void ScoreAgainstCentres(const BasisView& basis, const PixelObservations& obs, int first, int count,
                         const std::vector<std::vector<Candidate>>& lists,
                         const std::vector<std::vector<int>>& groups, const PooledModel& model,
                         const PixelSolveOptions& solve, const NormalSearchOptions& o,
                         const DarkViews& dark, std::vector<std::vector<Candidate>>* scored) {
  *scored = lists;
#pragma omp parallel
  {
    CentreScorer scorer(basis, model, solve.lookup, dark);
#pragma omp for schedule(dynamic, 16)
    for (int p = 0; p < count; ++p)
      scorer.Score(obs, first + p, groups[p], o, solve.MinObservations(), &(*scored)[p]);
  }
}

}  // namespace

const char* NormalCriterionName(NormalCriterion criterion) {
  switch (criterion) {
    case NormalCriterion::kFit:
      return "fit";
    case NormalCriterion::kHeldOut:
      return "held-out";
    case NormalCriterion::kCentre:
      return "centre";
  }
  return "?";
}

std::optional<NormalCriterion> ParseNormalCriterion(const std::string& name) {
  for (NormalCriterion c :
       {NormalCriterion::kFit, NormalCriterion::kHeldOut, NormalCriterion::kCentre})
    if (name == NormalCriterionName(c)) return c;
  return std::nullopt;
}

const char* NormalConfirmationName(NormalConfirmation c) {
  switch (c) {
    case NormalConfirmation::kAlone:
      return "alone";
    case NormalConfirmation::kRegrouped:
      return "regrouped";
    case NormalConfirmation::kAll:
      return "all";
  }
  return "?";
}

std::optional<NormalConfirmation> ParseNormalConfirmation(const std::string& name) {
  for (NormalConfirmation c :
       {NormalConfirmation::kAlone, NormalConfirmation::kRegrouped, NormalConfirmation::kAll})
    if (name == NormalConfirmationName(c)) return c;
  return std::nullopt;
}

const char* NormalSearchMethodName(NormalSearchMethod method) {
  return method == NormalSearchMethod::kGrid ? "grid" : "quadratic";
}

std::optional<NormalSearchMethod> ParseNormalSearchMethod(const std::string& name) {
  for (NormalSearchMethod m : {NormalSearchMethod::kGrid, NormalSearchMethod::kQuadratic})
    if (name == NormalSearchMethodName(m)) return m;
  return std::nullopt;
}

void NormalSearchOptions::Check(const BasisView& basis) const {
  if (!enabled) return;
  if (!(max_tilt_deg > 0 && max_tilt_deg < 60))
    throw UserError("normals max tilt",
                    "must be in (0, 60) degrees, got " + std::to_string(max_tilt_deg));
  if (components < 1 || components > basis.components)
    throw UserError("normals k", "must be in [1, " + std::to_string(basis.components) + "]");
  if (!(prior >= 0)) throw UserError("normals prior", "must be >= 0");
  if (!(evidence >= 0)) throw UserError("normals evidence", "must be >= 0");
  if (!(min_tilt_deg >= 0 && min_tilt_deg < max_tilt_deg))
    throw UserError("normals min tilt",
                    "must be from 0 to under the search's cone (" + std::to_string(max_tilt_deg) +
                        " degrees), got " + std::to_string(min_tilt_deg),
                    "a tilt under it keeps the sample's normal; 0 keeps every tilt");
  if (!(estimated_min_cos >= 0 && estimated_min_cos < 1))
    throw UserError("normals estimated min cos", "must be in [0, 1)");
  if (levels < 0 || levels > 12) throw UserError("normals levels", "must be in [0, 12]");
  if (coarse_reach < 1 || coarse_reach > 4)
    throw UserError("normals coarse reach", "must be in [1, 4]");
  if (chunk_pixels < 1) throw UserError("normals chunk", "must be at least 1");
  if (!(max_uncertainty_deg >= 0))
    throw UserError("normals max uncertainty", "must be >= 0 degrees (0: no limit), got " +
                                                   std::to_string(max_uncertainty_deg));
  if (trimmed_views < 0 || trimmed_views > kMaxNormalsTrimmedViews)
    throw UserError("normals trimmed views",
                    "must be in [0, " + std::to_string(kMaxNormalsTrimmedViews) + "], got " +
                        std::to_string(trimmed_views),
                    "1 (the default) leaves the worst-explained view out of a candidate's score");
}

void PixelNormals::Resize(int pixels) {
  normal.assign(pixels, Eigen::Vector3f::UnitZ());
  status.assign(pixels, NormalStatus::kAssumed);
  uncertainty_deg.assign(pixels, kNoNormalUncertainty);
  mixed.assign(pixels, 0);
}

void ToFacetFrame(const Eigen::Vector3f& n, double min_cos, const PixelObservations& from,
                  int pixel, PixelObservations* to, int to_pixel) {
  const Eigen::Matrix3f r = FacetFromSample(n);
  for (int v = 0; v < from.views; ++v) {
    const std::size_t i = from.At(pixel, v), j = to->At(to_pixel, v);
    const Eigen::Vector3f& l = from.light[i];
    const Eigen::Vector3f& e = from.camera[i];
    to->light[j] = (r * l).normalized();
    to->camera[j] = (r * e).normalized();
    const float cos_in = to->light[j].z();
    const bool usable = cos_in > min_cos && to->camera[j].z() > min_cos && l.z() > 0;
    for (int c = 0; c < 3; ++c)
      to->rgb[3 * j + c] =
          usable ? from.rgb[3 * i + c] * l.z() / cos_in : std::numeric_limits<float>::quiet_NaN();
  }
}

namespace {

// One chunk's coarse-to-fine search: each pixel's best candidate, and the sample's normal
// scored, for the evidence test.
struct ChunkSearch {
  std::vector<Candidate> best, flat;
  // The candidate the data alone prefer (lowest misfit, the prior left out): on the cone's edge,
  // the relief is too steep for the search even where the prior pulled the best inside.
  std::vector<Candidate> by_data;
  // Criterion kCentre: the views seen dark that the best's facet faces (SeenDarkWhereLit).
  std::vector<int> seen_dark;
  // Per pixel, per level of the search: the level's step (slope units) and the lowest misfit
  // among its candidates at least half a step from the best it started from (Uncertainty).
  struct Ring {
    float step = 0;
    double misfit = std::numeric_limits<double>::infinity();
  };
  std::vector<std::vector<Ring>> rings;
  // PixelNormals::uncertainty_deg of the best: the largest step whose ring scored within the
  // 95% region of two parameters around the best's misfit.
  float Uncertainty(int p) const;
};

// Half the 95% quantile of chi-square with two degrees of freedom (5.99): a candidate whose
// profile log-likelihood, (N / 2) ln(misfit^2 / best misfit^2) over N residuals, lies within this
// of the best's is one the data cannot tell from it.
constexpr double kUncertaintyLogLikelihood = 5.99 / 2;

float ChunkSearch::Uncertainty(int p) const {
  const Candidate& b = best[std::size_t(p)];
  if (!(b.misfit > 0) || b.views <= 0) return 0;
  const double residuals = 3.0 * b.views;
  float radius = 0;
  for (const Ring& ring : rings[std::size_t(p)])
    if (residuals / 2 * std::log(ring.misfit * ring.misfit / (b.misfit * b.misfit)) <
        kUncertaintyLogLikelihood)
      radius = std::max(radius, float(RadToDeg(std::atan(ring.step))));
  return radius;
}

// The minimum of the quadratic through a 3 x 3 grid of scores f[a + 1][b + 1] at offsets
// (a, b) steps from its centre (least squares: 9 values, 6 coefficients), in steps and clamped
// to the grid; nothing when the fit is not a bowl or a score is missing.
std::optional<Eigen::Vector2f> QuadraticMinimum(const double f[3][3]) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (!std::isfinite(f[a][b])) return std::nullopt;
  double gx = 0, gy = 0, hxx = 0, hyy = 0;
  for (int i = 0; i < 3; ++i) {
    gx += (f[2][i] - f[0][i]) / 6;
    gy += (f[i][2] - f[i][0]) / 6;
    hxx += (f[2][i] + f[0][i] - 2 * f[1][i]) / 3;
    hyy += (f[i][2] + f[i][0] - 2 * f[i][1]) / 3;
  }
  const double hxy = (f[2][2] - f[2][0] - f[0][2] + f[0][0]) / 4;
  const double det = hxx * hyy - hxy * hxy;
  if (!(hxx > 0 && det > 0)) return std::nullopt;
  const double dx = -(hyy * gx - hxy * gy) / det, dy = -(hxx * gy - hxy * gx) / det;
  return Eigen::Vector2f(float(std::clamp(dx, -1.0, 1.0)), float(std::clamp(dy, -1.0, 1.0)));
}

// Criterion kCentre: each pixel's views seen dark at its best normal (SeenDarkWhereLit).
void CountSeenDark(const BasisView& basis, const PixelObservations& obs, int first,
                   const PooledModel& reference, const PixelSolveOptions& solve,
                   const NormalSearchOptions& o, const DarkViews& dark, ChunkSearch* c) {
#pragma omp parallel
  {
    CentreScorer scorer(basis, reference, solve.lookup, dark);
#pragma omp for schedule(dynamic, 64)
    for (int p = 0; p < int(c->best.size()); ++p)
      if (c->best[p].group >= 0)
        c->seen_dark[p] = scorer.SeenDarkWhereLit(obs, first + p, c->best[p], o);
  }
}

ChunkSearch SearchChunk(const BasisView& basis, const PixelObservations& obs, int first, int count,
                        const PixelSolveOptions& solve, const NormalSearchOptions& o,
                        const PooledModel* reference) {
  const float cone = float(std::tan(DegToRad(o.max_tilt_deg)));
  ChunkSearch c;
  std::vector<std::vector<int>> groups =
      reference ? NearestGroups(basis, obs, first, count, *reference, solve)
                : std::vector<std::vector<int>>();
  const DarkViews dark(basis, obs, first, count, solve.lookup);
  const auto score = [&](const std::vector<std::vector<Candidate>>& lists) {
    std::vector<std::vector<Candidate>> scored;
    if (reference)
      ScoreAgainstCentres(basis, obs, first, count, lists, groups, *reference, solve, o, dark,
                          &scored);
    else
      ScoreCandidates(basis, obs, first, count, lists, solve, o, dark, &scored);
    return scored;
  };
  const auto keep_best = [&](int p, const std::vector<Candidate>& scored) {
    for (const Candidate& cand : scored) {
      if (cand.views < c.flat[p].views - kViewsItMayLose) continue;
      if (cand.score < c.best[p].score) c.best[p] = cand;
      if (cand.misfit < c.by_data[p].misfit) c.by_data[p] = cand;
    }
  };
  c.best.assign(count, Candidate{Eigen::Vector2f::Zero()});
  c.by_data = c.best;
  c.flat.resize(count);
  const bool quadratic = o.method == NormalSearchMethod::kQuadratic;
  // Per pixel, the last level's 3 x 3 scores around the best it started from.
  std::vector<std::array<std::array<double, 3>, 3>> last(count);
  std::vector<Eigen::Vector2f> last_centre(count);
  float step = cone / 2;
  for (int level = 0; level <= o.Levels(); ++level, step /= 2) {
    const int reach = level == 0 ? o.coarse_reach : 1;  // the coarse grid, then 3 x 3
    std::vector<std::vector<Candidate>> lists(count);
    for (int p = 0; p < count; ++p)
      for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b) {
          if (level > 0 && a == 0 && b == 0) continue;  // the best so far, scored already
          const Eigen::Vector2f s = c.best[p].slope + step * Eigen::Vector2f(float(a), float(b));
          if (s.norm() <= cone * 1.0001f) lists[p].push_back({s});
        }
    const std::vector<std::vector<Candidate>> scored = score(lists);
    if (level == 0) c.rings.assign(count, {});
    for (int p = 0; p < count; ++p) {
      ChunkSearch::Ring ring{step};
      for (const Candidate& cand : scored[p])
        if ((cand.slope - c.best[p].slope).norm() > 0.5f * step)
          ring.misfit = std::min(ring.misfit, cand.misfit);
      c.rings[p].push_back(ring);
      if (level == 0)
        for (const Candidate& cand : scored[p])
          if (cand.slope.isZero()) c.flat[p] = cand;
      if (level == o.Levels() && level > 0) {
        auto& f = last[p];
        for (auto& row : f) row.fill(std::numeric_limits<double>::infinity());
        last_centre[p] = c.best[p].slope;
        f[1][1] = c.best[p].score;
        for (const Candidate& cand : scored[p]) {
          const Eigen::Vector2f d = (cand.slope - last_centre[p]) / step;
          f[int(std::lround(d.x())) + 1][int(std::lround(d.y())) + 1] = cand.score;
        }
      }
      keep_best(p, scored[p]);
      // The coarse grid chose the group (jointly with the tilt); the refinements keep it.
      if (level == 0 && reference && c.best[p].group >= 0) {
        groups[p] = {c.best[p].group};
        if (c.best[p].second >= 0) groups[p].push_back(c.best[p].second);
      }
    }
  }
  if (quadratic && o.Levels() > 0) {
    // A Newton step on the quadratic through the last level's 3 x 3: one candidate more a pixel.
    step *= 2;  // the last level's
    std::vector<std::vector<Candidate>> lists(count);
    for (int p = 0; p < count; ++p) {
      double f[3][3];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) f[a][b] = last[p][a][b];
      const std::optional<Eigen::Vector2f> d = QuadraticMinimum(f);
      if (!d) continue;
      const Eigen::Vector2f s = last_centre[p] + step * *d;
      if (s.norm() <= cone * 1.0001f && s != c.best[p].slope) lists[p].push_back({s});
    }
    const std::vector<std::vector<Candidate>> scored = score(lists);
    for (int p = 0; p < count; ++p) keep_best(p, scored[p]);
  }
  c.seen_dark.assign(count, 0);
  if (reference) CountSeenDark(basis, obs, first, *reference, solve, o, dark, &c);
  return c;
}

}  // namespace

PixelNormals EstimateNormals(const BasisView& basis, PixelObservations* obs,
                             const PixelSolveOptions& solve, const NormalSearchOptions& o,
                             const PooledModel* reference) {
  o.Check(basis);
  PixelNormals out;
  out.Resize(obs->pixels);
  if (!o.enabled) return out;
  const bool by_centre = o.criterion == NormalCriterion::kCentre;
  if (by_centre && (!reference || reference->groups.empty())) return out;
  const float cone = float(std::tan(DegToRad(o.max_tilt_deg)));
  const float min_slope = float(std::tan(DegToRad(o.min_tilt_deg)));
  for (int first = 0; first < obs->pixels; first += o.chunk_pixels) {
    const int count = std::min(o.chunk_pixels, obs->pixels - first);
    const ChunkSearch c =
        SearchChunk(basis, *obs, first, count, solve, o, by_centre ? reference : nullptr);
    for (int p = 0; p < count; ++p) {
      const Candidate& best = c.best[p];
      if (!std::isfinite(best.score)) continue;  // no usable candidate: kAssumed
      // A view the best facet faces yet seen dark: the true facet turns away from it, steeper
      // than the cone, whether or not a centre explains the pixel at the best.
      if (c.seen_dark[p] > 0) {
        out.status[first + p] = NormalStatus::kRefused;
        continue;
      }
      // No centre explains the pixel even at its best normal: nothing to judge the normal by.
      if (by_centre && best.misfit > reference->groups[best.group].misfit_limit) continue;
      // A minimum on the cone's edge is not a minimum: the true tilt may lie beyond.
      if (best.slope.norm() >= cone * 0.98f || c.by_data[p].slope.norm() >= cone * 0.98f) {
        out.status[first + p] = NormalStatus::kRefused;
        continue;
      }
      // A tilt that only another material explains (NormalSearchOptions::same_centre).
      const bool other_centre = by_centre && o.same_centre && reference->groups_are_materials &&
                                best.second < 0 && c.flat[p].group >= 0 &&
                                best.group != c.flat[p].group;
      if (!TiltEarnsItsKeep(c.flat[p], best, o.evidence) || best.slope.norm() < min_slope ||
          other_centre) {
        out.status[first + p] = NormalStatus::kNoEvidence;
        continue;
      }
      out.uncertainty_deg[first + p] = c.Uncertainty(p);
      // The data fix the normal less well than the user asked for.
      if (o.max_uncertainty_deg > 0 && out.uncertainty_deg[first + p] > o.max_uncertainty_deg) {
        out.status[first + p] = NormalStatus::kRefused;
        continue;
      }
      const Eigen::Vector3f n = NormalOfSlope(best.slope.x(), best.slope.y());
      out.normal[first + p] = n;
      out.status[first + p] = NormalStatus::kEstimated;
      out.mixed[first + p] = best.second >= 0;
      ToFacetFrame(n, std::max(o.min_cos, o.estimated_min_cos), CopyPixels(*obs, first + p, 1), 0,
                   obs, first + p);
    }
  }
  return out;
}

namespace {

// Each sample pixel's group in the reference: the nearest to its flat independent solve, as the
// search picks its candidates; members per group.
std::vector<std::vector<int>> ReferenceMembers(const BasisView& basis,
                                               const PixelObservations& sample,
                                               const PooledModel& model,
                                               const PixelSolveOptions& solve, int chunk) {
  std::vector<std::vector<int>> members(model.groups.size());
  for (int first = 0; first < sample.pixels; first += chunk) {
    const int count = std::min(chunk, sample.pixels - first);
    const std::vector<std::vector<int>> nearest =
        NearestGroups(basis, sample, first, count, model, solve);
    for (int p = 0; p < count; ++p)
      if (!nearest[std::size_t(p)].empty())
        members[std::size_t(nearest[std::size_t(p)][0])].push_back(first + p);
  }
  return members;
}

// The model with group g alone: the centre a relief test judges by.
PooledModel GroupAlone(const PooledModel& model, int g) {
  PooledModel alone = model;
  alone.groups = {model.groups[std::size_t(g)]};
  return alone;
}

// Each pixel's misfit (RMS, log space) to the centre of `alone` (one group) at the best normal
// the search finds; infinite where none is usable.
std::vector<double> MisfitsAtBest(const BasisView& basis, const PixelObservations& pixels,
                                  const PooledModel& alone, const PixelSolveOptions& solve,
                                  const NormalSearchOptions& search) {
  std::vector<double> misfit;
  for (int first = 0; first < pixels.pixels; first += search.chunk_pixels) {
    const int count = std::min(search.chunk_pixels, pixels.pixels - first);
    const ChunkSearch c = SearchChunk(basis, pixels, first, count, solve, search, &alone);
    for (int p = 0; p < count; ++p) misfit.push_back(c.best[p].misfit);
  }
  return misfit;
}

// The same at the sample's normal: the one candidate the search scores as ChunkSearch::flat.
std::vector<double> MisfitsAtSampleNormal(const BasisView& basis, const PixelObservations& pixels,
                                          const PooledModel& alone, const PixelSolveOptions& solve,
                                          const NormalSearchOptions& search) {
  std::vector<double> misfit;
  for (int first = 0; first < pixels.pixels; first += search.chunk_pixels) {
    const int count = std::min(search.chunk_pixels, pixels.pixels - first);
    const DarkViews dark(basis, pixels, first, count, solve.lookup);
    const std::vector<std::vector<Candidate>> flat(count, {Candidate{Eigen::Vector2f::Zero()}});
    std::vector<std::vector<Candidate>> scored;
    ScoreAgainstCentres(basis, pixels, first, count, flat,
                        NearestGroups(basis, pixels, first, count, alone, solve), alone, solve,
                        search, dark, &scored);
    for (int p = 0; p < count; ++p) misfit.push_back(scored[p][0].misfit);
  }
  return misfit;
}

// The median over the pixels of a's misfit at their best normals over b's at the sample's.
double MedianRatio(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> ratio;
  for (std::size_t p = 0; p < a.size(); ++p)
    if (std::isfinite(a[p]) && std::isfinite(b[p]) && b[p] > 0) ratio.push_back(a[p] / b[p]);
  return ratio.empty() ? std::numeric_limits<double>::infinity() : Median(ratio);
}

// Takes out of the reference each group that is a larger group's relief: one whose pixels the
// larger group's centre, at the normals the search finds for them, explains better (median
// misfit ratio under kReliefRatio) than the group's own centre does at the sample's normal.
void DropReliefGroups(const BasisView& basis, const PixelObservations& sample,
                      const PixelSolveOptions& solve, const NormalSearchOptions& search,
                      PooledModel* model) {
  search.Check(basis);
  const std::size_t groups = model->groups.size();
  const std::vector<std::vector<int>> members =
      ReferenceMembers(basis, sample, *model, solve, search.chunk_pixels);
  std::vector<int> order(groups);
  for (std::size_t g = 0; g < groups; ++g) order[g] = int(g);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return members[a].size() > members[b].size(); });
  std::vector<char> keep(groups, 1);
  for (std::size_t i = 1; i < groups; ++i) {
    const int b = order[i];
    if (members[b].empty()) continue;
    const PixelObservations pixels = sample.Gather(members[b]);
    const std::vector<double> own =
        MisfitsAtSampleNormal(basis, pixels, GroupAlone(*model, b), solve, search);
    for (std::size_t j = 0; j < i && keep[b]; ++j) {
      const int a = order[j];
      if (!keep[a]) continue;
      const std::vector<double> by_a =
          MisfitsAtBest(basis, pixels, GroupAlone(*model, a), solve, search);
      if (MedianRatio(by_a, own) < kReliefRatio) keep[b] = 0;
    }
  }
  std::vector<PooledGroup> kept;
  for (std::size_t g = 0; g < groups; ++g)
    if (keep[g]) kept.push_back(std::move(model->groups[g]));
  model->groups = std::move(kept);
}

// WeighViewsByScatter: a view's squared misfit floored at this share of the mean over views, so
// that a view the centre happens to fit almost exactly does not take the whole score.
constexpr double kViewScatterFloor = 0.1;
// Fewer sample pixels than this in a group: its views stay unweighted (a median of fewer is
// noise).
constexpr int kMinScatterMembers = 30;

// Each group's views weighted by how well its centre predicts its own sample pixels there
// (NormalSearchOptions::view_weights): w_v = mean_u(m_u) / m_v, m_v the median over the group's
// pixels of the view's squared misfit (3 channels) at the sample's normal, floored.
void WeighViewsByScatter(const BasisView& basis, const PixelObservations& sample,
                         const PixelSolveOptions& solve, const NormalSearchOptions& search,
                         PooledModel* model) {
  const std::vector<std::vector<int>> members =
      ReferenceMembers(basis, sample, *model, solve, search.chunk_pixels);
  for (std::size_t g = 0; g < model->groups.size(); ++g) {
    if (int(members[g].size()) < kMinScatterMembers) continue;
    const PixelObservations pixels = sample.Gather(members[g]);
    const DarkViews dark(basis, pixels, 0, 0, solve.lookup);
    CentreScorer scorer(basis, *model, solve.lookup, dark);
    std::vector<std::vector<double>> per_view(std::size_t(pixels.views));
    for (int p = 0; p < pixels.pixels; ++p) {
      scorer.one.Resize(1, pixels.views);
      ToFacetFrame(Eigen::Vector3f::UnitZ(), search.min_cos, pixels, p, &scorer.one, 0);
      scorer.Prepare(model->groups[g].centre_components);
      scorer.Misfit(int(g), 0);
      for (std::size_t i = 0; i < scorer.used.size(); ++i)
        per_view[std::size_t(scorer.used[i])].push_back(scorer.view_misfit[i]);
    }
    std::vector<double> median(per_view.size(), 0.0);
    double sum = 0;
    int seen = 0;
    for (std::size_t v = 0; v < per_view.size(); ++v) {
      if (per_view[v].empty()) continue;
      median[v] = Median(per_view[v]);
      sum += median[v];
      ++seen;
    }
    if (seen == 0 || !(sum > 0)) continue;
    const double mean = sum / seen;
    std::vector<double>& w = model->groups[g].view_weight;
    w.assign(per_view.size(), 1.0);
    for (std::size_t v = 0; v < per_view.size(); ++v)
      if (!per_view[v].empty()) w[v] = mean / std::max(median[v], kViewScatterFloor * mean);
  }
}

}  // namespace

PooledModel FitNormalReference(const BasisView& basis, const PixelObservations& sample,
                               const PixelSolveOptions& solve, const PooledOptions& pooled,
                               const NormalSearchOptions& search) {
  PooledOptions reference = pooled;
  reference.centre_eta_fractions = {1, 1.0 / 4, 1.0 / 16, 1.0 / 64, 1.0 / 256};
  // Every pixel alike: a candidate normal is judged by how well the centre predicts the pixel's
  // own directions, wherever on the sample it lies, not the grid's error the plan's directions
  // were chosen for (weighted to them, the study's card at 4 degrees: normals over the relief
  // 2.16 against 1.08 degrees, false tilt 0.76 against 0.59).
  reference.design_sigma_deg = 0;
  reference.merge_in_field = false;
  reference.leave_out_colour_fringes = false;
  reference.groups_must_beat_independent = false;
  // The number of groups is searched past merges, as for the map's model: a search stopped at
  // them left a flat pink-jasper patch merged into the white paint around it, and tilted
  // (docs/reconstruction.md, "The reference's groups are materials"). The groups that are a
  // material's relief are taken out after.
  PooledModel model = FitPooledModel(basis, sample, solve, reference);
  // A number of groups the user forced is kept as fitted.
  if (pooled.groups <= 0 && search.enabled) {
    if (model.groups.size() > 1) DropReliefGroups(basis, sample, solve, search, &model);
    model.groups_are_materials = true;
  }
  if (search.view_weights) WeighViewsByScatter(basis, sample, solve, search, &model);
  return model;
}

}  // namespace acq
