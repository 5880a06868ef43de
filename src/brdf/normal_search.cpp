#include "brdf/normal_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
};

// Scores candidates[p] (one list per pixel of the chunk [first, first + count)) with one batch
// of the per-pixel solver.
void ScoreCandidates(const BasisView& basis, const PixelObservations& obs, int first, int count,
                     const std::vector<std::vector<Candidate>>& lists,
                     const PixelSolveOptions& solve, const NormalSearchOptions& o,
                     std::vector<std::vector<Candidate>>* scored) {
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
    cand.score = solution.residual[i] + o.prior * double(cand.slope.squaredNorm());
  }
}

}  // namespace

void NormalSearchOptions::Check(const BasisView& basis) const {
  if (!enabled) return;
  if (!(max_tilt_deg > 0 && max_tilt_deg < 60))
    throw UserError("normals max tilt",
                    "must be in (0, 60) degrees, got " + std::to_string(max_tilt_deg));
  if (components < 1 || components > basis.components)
    throw UserError("normals k", "must be in [1, " + std::to_string(basis.components) + "]");
  if (!(prior >= 0)) throw UserError("normals prior", "must be >= 0");
  if (levels < 0 || levels > 12) throw UserError("normals levels", "must be in [0, 12]");
  if (chunk_pixels < 1) throw UserError("normals chunk", "must be at least 1");
}

void PixelNormals::Resize(int pixels) {
  normal.assign(pixels, Eigen::Vector3f::UnitZ());
  status.assign(pixels, NormalStatus::kAssumed);
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

PixelNormals EstimateNormals(const BasisView& basis, PixelObservations* obs,
                             const PixelSolveOptions& solve, const NormalSearchOptions& o) {
  o.Check(basis);
  PixelNormals out;
  out.Resize(obs->pixels);
  if (!o.enabled) return out;
  const float cone = float(std::tan(DegToRad(o.max_tilt_deg)));
  for (int first = 0; first < obs->pixels; first += o.chunk_pixels) {
    const int count = std::min(o.chunk_pixels, obs->pixels - first);
    std::vector<int> flat_views(count, 0);  // the views the sample's normal's solve used
    std::vector<Candidate> best(count);     // the sample's normal, unscored
    float step = cone / 2;
    for (int level = 0; level <= o.levels; ++level, step /= 2) {
      const int reach = level == 0 ? 2 : 1;  // 5 x 5, then 3 x 3 around the best
      std::vector<std::vector<Candidate>> lists(count);
      for (int p = 0; p < count; ++p)
        for (int a = -reach; a <= reach; ++a)
          for (int b = -reach; b <= reach; ++b) {
            const Eigen::Vector2f s = best[p].slope + step * Eigen::Vector2f(float(a), float(b));
            if (s.norm() <= cone * 1.0001f) lists[p].push_back({s});
          }
      std::vector<std::vector<Candidate>> scored;
      ScoreCandidates(basis, *obs, first, count, lists, solve, o, &scored);
      for (int p = 0; p < count; ++p) {
        if (level == 0)
          for (const Candidate& c : scored[p])
            if (c.slope.isZero()) flat_views[p] = c.views;
        for (const Candidate& c : scored[p])
          if (c.score < best[p].score && c.views >= flat_views[p] - kViewsItMayLose) best[p] = c;
      }
    }
    for (int p = 0; p < count; ++p) {
      if (!std::isfinite(best[p].score)) continue;  // no usable candidate: kAssumed
      // A minimum on the cone's edge is not a minimum: the true tilt may lie beyond.
      if (best[p].slope.norm() >= cone * 0.98f) {
        out.status[first + p] = NormalStatus::kRefused;
        continue;
      }
      const Eigen::Vector3f n = NormalOfSlope(best[p].slope.x(), best[p].slope.y());
      out.normal[first + p] = n;
      out.status[first + p] = NormalStatus::kEstimated;
      const PixelObservations before = [&] {  // the pixel's own, copied: to and from overlap
        PixelObservations one;
        one.Resize(1, obs->views);
        for (int v = 0; v < obs->views; ++v) {
          one.light[v] = obs->light[obs->At(first + p, v)];
          one.camera[v] = obs->camera[obs->At(first + p, v)];
          for (int c = 0; c < 3; ++c) one.rgb[3 * v + c] = obs->rgb[3 * obs->At(first + p, v) + c];
        }
        return one;
      }();
      ToFacetFrame(n, o.min_cos, before, 0, obs, first + p);
    }
  }
  return out;
}

}  // namespace acq
