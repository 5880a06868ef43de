#include "acq/colour_chart_fit.h"

#include <Eigen/QR>
#include <algorithm>
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

// Least squares, all patches alike: C A^T = T with C and T one patch per row.
Eigen::Matrix3d FitMatrix(const std::vector<Eigen::Vector3d>& camera,
                          const std::vector<Eigen::Vector3d>& target) {
  Eigen::MatrixXd C(camera.size(), 3), T(camera.size(), 3);
  for (std::size_t i = 0; i < camera.size(); ++i) {
    C.row(Eigen::Index(i)) = camera[i].transpose();
    T.row(Eigen::Index(i)) = target[i].transpose();
  }
  return C.colPivHouseholderQr().solve(T).transpose();
}

double Residual(const Eigen::Matrix3d& a, const Eigen::Vector3d& camera,
                const Eigen::Vector3d& target) {
  const Eigen::Vector3d rgb = a * camera;
  return DeltaE2000(LabFromLinearRec709({rgb[0], rgb[1], rgb[2]}),
                    LabFromLinearRec709({target[0], target[1], target[2]}));
}

// The patches the fit uses: each one's index on the chart, its camera RGB and its reference.
struct UsedPatches {
  std::vector<int> index;
  std::vector<Eigen::Vector3d> camera, target;
  int Count() const { return int(index.size()); }
  void Add(int patch, const Eigen::Vector3d& rgb, const Eigen::Vector3d& reference) {
    index.push_back(patch);
    camera.push_back(rgb);
    target.push_back(reference);
  }
  int Remove(int i) {  // returns its index on the chart
    const int patch = index[std::size_t(i)];
    index.erase(index.begin() + i);
    camera.erase(camera.begin() + i);
    target.erase(target.begin() + i);
    return patch;
  }
};

std::string DroppedList(const std::vector<ChartPatchFit>& patches) {
  std::string dropped;
  for (const ChartPatchFit& p : patches)
    if (!p.used) dropped += (dropped.empty() ? "" : "; ") + p.name + ": " + p.dropped;
  return dropped;
}

}  // namespace

namespace {

// The fit of patch i read at reading i. Returns the fit, or nullopt with `problem` saying why
// too few patches remain.
std::optional<ChartFit> FitReadings(const std::vector<PatchReading>& readings,
                                    std::string* problem) {
  const auto& reference = ColorCheckerClassic();
  ChartFit fit;
  UsedPatches used;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    ChartPatchFit p;
    p.name = reference[i].name;
    if (readings[i].dropped) {
      p.dropped = *readings[i].dropped;
    } else {
      p.used = true;
      const auto& rgb = reference[i].rgb;
      used.Add(int(i), readings[i].camera, Eigen::Vector3d(rgb[0], rgb[1], rgb[2]));
    }
    fit.patches.push_back(p);
  }
  const auto enough = [&] {
    if (used.Count() >= kMinChartPatches) return true;
    *problem = "only " + std::to_string(used.Count()) + " of 24 colour chart patches are usable (" +
               DroppedList(fit.patches) + ")";
    return false;
  };
  if (!enough()) return std::nullopt;
  // A patch wholly under something uniform passes the spread test with another colour: it is
  // the one the fit misses by far. The worst is dropped and the rest fitted again (one at a
  // time: a wrong patch pulls the fit towards itself and raises the others' residuals).
  std::vector<double> residuals;
  for (;;) {
    fit.rec709_from_camera = FitMatrix(used.camera, used.target);
    residuals.clear();
    for (int i = 0; i < used.Count(); ++i)
      residuals.push_back(Residual(fit.rec709_from_camera, used.camera[std::size_t(i)],
                                   used.target[std::size_t(i)]));
    const auto worst = std::max_element(residuals.begin(), residuals.end());
    if (*worst <= kMaxChartResidual) break;
    char why[128];
    std::snprintf(why, sizeof why,
                  "%.0f CIEDE2000 from its reference colour after the fit (covered, or the chart "
                  "not where expected)",
                  *worst);
    ChartPatchFit& p = fit.patches[std::size_t(used.Remove(int(worst - residuals.begin())))];
    p.used = false;
    p.dropped = why;
    if (!enough()) return std::nullopt;
  }
  fit.used = used.Count();
  for (int i = 0; i < fit.used; ++i) {
    ChartPatchFit& p = fit.patches[std::size_t(used.index[std::size_t(i)])];
    const Eigen::Vector3d rgb = fit.rec709_from_camera * used.camera[std::size_t(i)];
    p.rgb = {rgb[0], rgb[1], rgb[2]};
    p.delta_e2000 = residuals[std::size_t(i)];
  }
  fit.max_delta_e2000 = *std::max_element(residuals.begin(), residuals.end());
  fit.median_delta_e2000 = Median(residuals);
  return fit;
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
  const int patches = layout.columns * layout.rows;
  const auto read_as = [&](ChartTurn turn) {
    ChartLayout laid = layout;
    laid.turn = turn;
    std::vector<PatchReading> readings;
    for (int i = 0; i < patches; ++i)
      readings.push_back(ReadPatch(chart, spectralon, to_image, laid.Centre(i), laid.patch_mm));
    return readings;
  };
  std::string problem, turned_problem;  // the refusal names the chart as laid
  if (std::optional<ChartFit> fit = FitReadings(read_as(layout.turn), &problem)) return *fit;
  // Laid turned (an easy mistake: half round the chart keeps its shape; a quarter round it fits
  // the sample as well), it is as good a chart: fitted as laid, and said. A patch read where a
  // turn puts it is a reading of the chart's own patch, or not uniform, or far from every fit.
  for (int quarters = 1; quarters < 4; ++quarters) {
    const ChartTurn turn = ChartTurn((int(layout.turn) + quarters) % 4);
    if (std::optional<ChartFit> fit = FitReadings(read_as(turn), &turned_problem)) {
      fit->turned = turn;
      return *fit;
    }
  }
  throw UserError(where, problem + " (nor laid turned by 90, 180 or 270 degrees)",
                  "lay the chart flat and centred, nothing over it, lit without glare; or give "
                  "camera.colour_matrix (a session captured already: acq session process "
                  "SESSION --set camera.colour_chart=not_fitted --set camera.colour_matrix=[9 "
                  "numbers], docs/colour.md)");
}

}  // namespace acq
