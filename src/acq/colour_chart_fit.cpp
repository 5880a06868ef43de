#include "acq/colour_chart_fit.h"

#include <Eigen/QR>
#include <cmath>
#include <cstdio>

#include "brdf/evaluation.h"
#include "core/colour.h"
#include "core/error.h"

namespace acq {
namespace {

// A patch's spread allowed, each channel's standard deviation over the patch's centre against
// the patch's grey (the mean of its channels: a saturated colour's faint channel is mostly noise
// of its own, which says nothing of the patch): the sensor's noise leaves a few percent; a patch
// half covered, or an edge within its centre, tens of percent.
constexpr double kMaxPatchSpread = 0.15;
constexpr int kSamplesPerSide = 7;       // a 7 x 7 grid ...
constexpr double kCentreFraction = 0.6;  // ... over the patch's central 60%

struct PatchReading {
  std::optional<std::string> dropped;
  Eigen::Vector3d camera = Eigen::Vector3d::Zero();  // camera RGB / Spectralon grey
};

PatchReading ReadPatch(const HdrImage& chart, const HdrImage& spectralon,
                       const SampleToImage& to_image, const Eigen::Vector2d& centre,
                       double side_mm) {
  const std::size_t n = std::size_t(chart.width) * std::size_t(chart.height);
  std::vector<Eigen::Vector3d> values;
  for (int j = 0; j < kSamplesPerSide; ++j)
    for (int i = 0; i < kSamplesPerSide; ++i) {
      const double step = kCentreFraction * side_mm / (kSamplesPerSide - 1);
      const Eigen::Vector2d point =
          centre +
          step * Eigen::Vector2d(i - (kSamplesPerSide - 1) / 2.0, j - (kSamplesPerSide - 1) / 2.0);
      const std::optional<Eigen::Vector2d> px = to_image(point);
      const int x = px ? int(std::lround(px->x())) : -1, y = px ? int(std::lround(px->y())) : -1;
      if (x < 0 || y < 0 || x >= chart.width || y >= chart.height) return {"off the image", {}};
      const std::size_t at = std::size_t(y) * chart.width + x;
      if (chart.flag[at] != kHdrOk) return {"saturated or dark", {}};
      if (spectralon.flag[at] != kHdrOk) return {"the Spectralon there saturated or dark", {}};
      const double grey = (spectralon.radiance[at] + spectralon.radiance[n + at] +
                           spectralon.radiance[2 * n + at]) /
                          3;
      if (!(grey > 0)) return {"no light on the Spectralon there", {}};
      values.emplace_back(chart.radiance[at] / grey, chart.radiance[n + at] / grey,
                          chart.radiance[2 * n + at] / grey);
    }
  PatchReading r;
  for (const Eigen::Vector3d& v : values) r.camera += v / double(values.size());
  const double grey = std::max(r.camera.mean(), 1e-12);
  for (int c = 0; c < 3; ++c) {
    double var = 0;
    for (const Eigen::Vector3d& v : values) var += (v[c] - r.camera[c]) * (v[c] - r.camera[c]);
    const double spread = std::sqrt(var / double(values.size())) / grey;
    if (spread > kMaxPatchSpread) {
      char why[96];
      std::snprintf(why, sizeof why, "not uniform (%.0f%% spread: covered, or not where expected)",
                    100 * spread);
      return {std::string(why), {}};
    }
  }
  return r;
}

}  // namespace

ChartFit FitColourChart(const HdrImage& chart, const HdrImage& spectralon,
                        const SampleToImage& to_image, const std::string& where,
                        const ChartLayout& layout) {
  if (chart.channels != 3 || spectralon.channels != 3 || chart.width != spectralon.width ||
      chart.height != spectralon.height)
    throw UserError(where,
                    "the chart and the Spectralon at its pose must be colour images of one size",
                    "capture both with the colour camera at the same pose");
  const auto& reference = ColorCheckerClassic();
  ChartFit fit;
  std::vector<Eigen::Vector3d> camera, target;
  std::vector<int> used_patch;
  for (int i = 0; i < int(reference.size()); ++i) {
    ChartPatchFit p;
    p.name = reference[std::size_t(i)].name;
    const PatchReading r =
        ReadPatch(chart, spectralon, to_image, layout.Centre(i), layout.patch_mm);
    if (r.dropped) {
      p.dropped = *r.dropped;
    } else {
      p.used = true;
      camera.push_back(r.camera);
      const auto& rgb = reference[std::size_t(i)].rgb;
      target.emplace_back(rgb[0], rgb[1], rgb[2]);
      used_patch.push_back(i);
    }
    fit.patches.push_back(p);
  }
  fit.used = int(camera.size());
  if (fit.used < kMinChartPatches) {
    std::string dropped;
    for (const ChartPatchFit& p : fit.patches)
      if (!p.used) dropped += (dropped.empty() ? "" : "; ") + p.name + ": " + p.dropped;
    throw UserError(where,
                    "only " + std::to_string(fit.used) +
                        " of 24 colour chart patches are usable (" + dropped + ")",
                    "lay the chart flat and centred, nothing over it, lit without glare; or give "
                    "camera.colour_matrix");
  }
  // Least squares, all patches alike: C A^T = T with C and T one patch per row.
  Eigen::MatrixXd C(fit.used, 3), T(fit.used, 3);
  for (int i = 0; i < fit.used; ++i) {
    C.row(i) = camera[std::size_t(i)].transpose();
    T.row(i) = target[std::size_t(i)].transpose();
  }
  fit.rec709_from_camera = C.colPivHouseholderQr().solve(T).transpose();
  std::vector<double> errors;
  for (int i = 0; i < fit.used; ++i) {
    const Eigen::Vector3d rgb = fit.rec709_from_camera * camera[std::size_t(i)];
    ChartPatchFit& p = fit.patches[std::size_t(used_patch[std::size_t(i)])];
    p.rgb = {rgb[0], rgb[1], rgb[2]};
    const auto& t = target[std::size_t(i)];
    p.delta_e2000 = DeltaE2000(LabFromLinearRec709(p.rgb), LabFromLinearRec709({t[0], t[1], t[2]}));
    errors.push_back(p.delta_e2000);
    fit.max_delta_e2000 = std::max(fit.max_delta_e2000, p.delta_e2000);
  }
  fit.median_delta_e2000 = Median(errors);
  return fit;
}

}  // namespace acq
