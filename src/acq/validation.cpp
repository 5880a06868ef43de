#include "acq/validation.h"

#include <cmath>

#include "brdf/evaluation.h"
#include "core/colour.h"
#include "core/error.h"

namespace acq {

ValidationResult CompareWithCapture(const SvbrdfMap& map, const BasisView& basis, SessionView view,
                                    RowLookup lookup) {
  ValidationResult result;
  result.name = view.name;
  const int w = map.info.width, h = map.info.height, k = map.info.components;
  std::vector<SessionView> one;
  one.push_back(std::move(view));
  CorrespondenceSource source(std::move(one), map.info.pixel_size_mm);
  if (source.Width() != w || source.Height() != h)
    throw UserError(result.name,
                    "the validation view's correspondence map is " +
                        std::to_string(source.Width()) + " x " + std::to_string(source.Height()) +
                        ", the SVBRDF map " + std::to_string(w) + " x " + std::to_string(h),
                    "compute both from the same reference view");
  // The captured BRDF per pixel, with its true directions, from the same radiometry the
  // reconstruction used.
  const PixelObservations obs = source.Rows(0, h);
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  result.predicted = {w, h, std::vector<float>(pixels * 3, 0.0f)};
  result.captured = result.predicted;
  std::vector<char> compared(pixels, 0);
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      const float* rgb = &obs.rgb[3 * obs.At(int(p), 0)];
      // As the solver: an observation counts only with all three channels.
      if (map.Plane("valid", x, y) == 0 ||
          !(std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2])))
        continue;
      const Eigen::Vector3d in = obs.light[obs.At(int(p), 0)].cast<double>();
      const Eigen::Vector3d out = obs.camera[obs.At(int(p), 0)].cast<double>();
      const std::vector<float> c = PixelCoefficients(map, x, y);
      const auto rho = BrdfFromCoefficients(basis, c.data(), k, in, out, lookup);
      const double cos_in = std::max(in.z(), 0.0);
      for (int ch = 0; ch < 3; ++ch) {
        result.predicted.rgb[3 * p + ch] = float(rho[ch] * cos_in);
        result.captured.rgb[3 * p + ch] = float(rgb[ch] * cos_in);
      }
      compared[p] = 1;
    }
  double diff2 = 0, ref2 = 0;
  std::vector<double> relative, delta_e;
  constexpr double kPi = 3.14159265358979323846;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (!compared[p]) continue;
    for (int ch = 0; ch < 3; ++ch) {
      const double a = result.predicted.rgb[3 * p + ch], b = result.captured.rgb[3 * p + ch];
      diff2 += (a - b) * (a - b);
      ref2 += b * b;
      if (b > 0) relative.push_back(std::abs(a - b) / b);
    }
    const float* a = &result.predicted.rgb[3 * p];
    const float* b = &result.captured.rgb[3 * p];
    delta_e.push_back(DeltaE2000(LabFromLinearRec709({kPi * a[0], kPi * a[1], kPi * a[2]}),
                                 LabFromLinearRec709({kPi * b[0], kPi * b[1], kPi * b[2]})));
    ++result.pixels;
  }
  result.median_delta_e2000 = delta_e.empty() ? 0 : Median(delta_e);
  result.relative_rms = ref2 > 0 ? std::sqrt(diff2 / ref2) : 0;
  result.median_relative = relative.empty() ? 0 : Median(relative);
  return result;
}

}  // namespace acq
