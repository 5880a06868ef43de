#include "acq/map_score.h"

#include <Eigen/Core>

#include <cmath>
#include <limits>

#include "acq/map_render.h"
#include "brdf/basis_rows.h"
#include "brdf/evaluation.h"
#include "brdf/fov_evaluation.h"
#include "brdf/normal_search.h"
#include "core/angles.h"
#include "core/colour.h"
#include "core/error.h"
#include "core/facet_frame.h"

namespace acq {
DirectionPair DiffuseColourDirections() {
  const double s = std::sqrt(0.5);
  return {Eigen::Vector3d(s, 0, s), Eigen::Vector3d(0, 0, 1)};
}

MapScore ScoreMap(const SvbrdfMap& map, const BasisView& basis, const std::vector<int>& label,
                  const std::vector<MerlBrdf>& truth) {
  const int w = map.info.width, h = map.info.height, k = map.info.components;
  if (label.size() != std::size_t(w) * std::size_t(h))
    throw UserError("ground truth", "has " + std::to_string(label.size()) +
                                        " labels for a map of " + std::to_string(w) + " x " +
                                        std::to_string(h) + " pixels");
  if (basis.components < k)
    throw UserError("basis", "has fewer components than the map (" + std::to_string(k) + ")",
                    "give the basis the map was reconstructed with (" + map.info.basis + ")");
  const HeldOutSet held(basis, truth);
  MapScore score;
  score.log_rmse.assign(label.size(), -1.0f);
  std::vector<double> all, valid, albedo_delta_e;
  std::array<std::vector<double>, 3> by_channel;
  const DirectionPair diffuse = DiffuseColourDirections();
  // Each material's true diffuse colour as a reflectance (pi f), in Lab: once, not per pixel.
  std::vector<Lab> true_diffuse;
  for (const MerlBrdf& m : truth) {
    const std::array<double, 3> f = m.Lookup(diffuse.in, diffuse.out);
    true_diffuse.push_back(LabFromLinearRec709({kPi * f[0], kPi * f[1], kPi * f[2]}));
  }
  const RowLookup lookup = ParseRowLookup(map.info.lookup).value_or(RowLookup::kNearest);
  std::vector<std::vector<double>> by_material(truth.size()), albedo_by_material(truth.size());
  std::vector<Eigen::Vector3d> albedo_sum(truth.size(), Eigen::Vector3d::Zero());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      if (label[p] < 0) continue;
      const bool is_valid = map.Plane("valid", x, y) != 0;
      double sum = 0;
      for (int c = 0; c < 3; ++c) {
        const std::vector<float> cf = map.Coefficients(x, y, c);
        const Eigen::Map<const Eigen::VectorXf> coeff(cf.data(), k);
        const double e = held.LogRmse(label[p] * 3 + c, coeff.cast<double>());
        all.push_back(e);
        by_channel[c].push_back(e);
        if (is_valid) valid.push_back(e);
        sum += e;
      }
      const std::vector<float> c = PixelCoefficients(map, x, y);
      const std::array<double, 3> f =
          BrdfFromCoefficients(basis, c.data(), k, diffuse.in, diffuse.out, lookup);
      const double albedo_e = DeltaE2000(LabFromLinearRec709({kPi * f[0], kPi * f[1], kPi * f[2]}),
                                         true_diffuse[std::size_t(label[p])]);
      albedo_delta_e.push_back(albedo_e);
      albedo_by_material[std::size_t(label[p])].push_back(albedo_e);
      albedo_sum[std::size_t(label[p])] += kPi * Eigen::Vector3d(f[0], f[1], f[2]);
      score.log_rmse[p] = float(sum / 3);
      by_material.at(std::size_t(label[p])).push_back(sum / 3);
      ++score.pixels;
      score.valid += is_valid;
    }
  for (const std::vector<double>& m : by_material)
    score.material_median_log_rmse.push_back(m.empty() ? 0 : Median(m));
  for (std::size_t m = 0; m < truth.size(); ++m) {
    const std::vector<double>& e = albedo_by_material[m];
    score.material_albedo_delta_e2000_median.push_back(e.empty() ? 0 : Median(e));
    const Eigen::Vector3d mean = albedo_sum[m] / std::max<double>(1, double(e.size()));
    score.material_albedo_mean_delta_e2000.push_back(
        e.empty() ? 0
                  : DeltaE2000(LabFromLinearRec709({mean[0], mean[1], mean[2]}), true_diffuse[m]));
  }
  for (int c = 0; c < 3; ++c)
    score.channel_median_log_rmse[c] = by_channel[c].empty() ? 0 : Median(by_channel[c]);
  score.albedo_delta_e2000_median = albedo_delta_e.empty() ? 0 : Median(albedo_delta_e);
  score.median_log_rmse = all.empty() ? 0 : Median(all);
  score.median_log_rmse_valid = valid.empty() ? 0 : Median(valid);
  return score;
}

namespace {

// Whether another material lies within kInkEdgeReach pixels of (x, y).
bool NearInkEdge(const std::vector<int>& labels, int w, int h, int x, int y) {
  const int own = labels[std::size_t(y) * w + x];
  for (int dy = -kInkEdgeReach; dy <= kInkEdgeReach; ++dy)
    for (int dx = -kInkEdgeReach; dx <= kInkEdgeReach; ++dx) {
      const int u = std::clamp(x + dx, 0, w - 1), v = std::clamp(y + dy, 0, h - 1);
      if (labels[std::size_t(v) * w + u] != own) return true;
    }
  return false;
}

double MedianOrNan(const std::vector<double>& v) {
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : Median(v);
}

}  // namespace

NormalScore ScoreNormals(const SvbrdfMap& map, const std::vector<Eigen::Vector3f>& truth,
                         const std::vector<int>& labels) {
  const int w = map.info.width, h = map.info.height;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  if (truth.size() != pixels || (!labels.empty() && labels.size() != pixels))
    throw UserError("normal score", "the truth has " + std::to_string(truth.size()) +
                                        " normals and " + std::to_string(labels.size()) +
                                        " labels for a map of " + std::to_string(w) + " x " +
                                        std::to_string(h) + " pixels");
  std::vector<double> relief, assumed, flat, one_material, ink_edges;
  std::vector<double> uncertainty, certain, uncertain;
  std::vector<std::vector<double>> flat_by_material;
  NormalScore score;
  score.error_deg.resize(truth.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3f& t = truth[std::size_t(y) * w + x];
      const Eigen::Vector3f got(map.Plane("normal.x", x, y), map.Plane("normal.y", x, y),
                                map.Plane("normal.z", x, y));
      const float status = map.Plane("normal_status", x, y);
      score.refused += status == float(NormalStatus::kRefused);
      score.no_evidence += status == float(NormalStatus::kNoEvidence);
      const double tilt = NormalAngle(t, Eigen::Vector3f::UnitZ());
      const double error = RadToDeg(NormalAngle(t, got.normalized()));
      score.error_deg[std::size_t(y) * w + x] = float(error);
      if (tilt < DegToRad(0.05)) {
        flat.push_back(error);
        const int label = labels.empty() ? -1 : labels[std::size_t(y) * w + x];
        if (label >= 0) {
          if (flat_by_material.size() <= std::size_t(label)) flat_by_material.resize(label + 1);
          flat_by_material[std::size_t(label)].push_back(error);
        }
      }
      const float radius = map.Plane("normal_uncertainty_deg", x, y);
      // A map written before the plane reads -1 there: no uncertainty to split by.
      const bool estimated = status == float(NormalStatus::kEstimated) && radius >= 0;
      if (estimated) uncertainty.push_back(radius);
      if (!(tilt > DegToRad(0.5))) continue;
      relief.push_back(error);
      if (estimated) (radius <= kCertainNormalDeg ? certain : uncertain).push_back(error);
      assumed.push_back(RadToDeg(tilt));
      if (!labels.empty())
        (NearInkEdge(labels, w, h, x, y) ? ink_edges : one_material).push_back(error);
    }
  score.median_error_deg_relief = MedianOrNan(relief);
  score.median_error_deg_relief_assumed_flat = MedianOrNan(assumed);
  score.median_tilt_deg_flat = MedianOrNan(flat);
  score.median_error_deg_relief_one_material = MedianOrNan(one_material);
  score.median_error_deg_relief_ink_edges = MedianOrNan(ink_edges);
  for (const std::vector<double>& m : flat_by_material)
    score.material_median_tilt_deg_flat.push_back(MedianOrNan(m));
  score.relief_pixels = long(relief.size());
  score.flat_pixels = long(flat.size());
  score.relief_pixels_one_material = long(one_material.size());
  score.relief_pixels_ink_edges = long(ink_edges.size());
  score.median_uncertainty_deg = MedianOrNan(uncertainty);
  score.median_error_deg_relief_certain = MedianOrNan(certain);
  score.median_error_deg_relief_uncertain = MedianOrNan(uncertain);
  score.relief_pixels_certain = long(certain.size());
  score.relief_pixels_uncertain = long(uncertain.size());
  return score;
}

}  // namespace acq
