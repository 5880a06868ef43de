#include "acq/validation.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "brdf/evaluation.h"
#include "core/colour.h"
#include "core/error.h"
#include "io/float_planes_exr.h"

namespace acq {

PixelBrdf MapPixelBrdf(const SvbrdfMap& map, const BasisView& basis, RowLookup lookup) {
  return
      [&map, &basis, lookup](int x, int y, const Eigen::Vector3d& in, const Eigen::Vector3d& out) {
        return MapBrdfAt(map, basis, x, y, in, out, lookup);
      };
}

ValidationData CaptureOfView(const SvbrdfMap& map, SessionView view) {
  ValidationData data;
  data.name = view.name;
  const int w = map.info.width, h = map.info.height;
  // Copied before the view moves into the source, which checks the planes' sizes.
  const std::vector<float> view_x = view.correspondence.Plane("x", view.name),
                           view_y = view.correspondence.Plane("y", view.name);
  std::vector<SessionView> one;
  one.push_back(std::move(view));
  CorrespondenceSource source(std::move(one), map.info.pixel_size_mm);
  if (source.Width() != w || source.Height() != h)
    throw UserError(data.name,
                    "the validation view's correspondence map is " +
                        std::to_string(source.Width()) + " x " + std::to_string(source.Height()) +
                        ", the SVBRDF map " + std::to_string(w) + " x " + std::to_string(h),
                    "compute both from the same reference view");
  // The captured BRDF per pixel, with its true directions, from the same radiometry the
  // reconstruction used.
  const PixelObservations obs = source.Rows(0, h);
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  data.width = w;
  data.height = h;
  data.captured.assign(pixels * 3, 0.0f);
  data.light.assign(pixels * 3, 0.0f);
  data.camera.assign(pixels * 3, 0.0f);
  data.compared.assign(pixels, 0);
  data.positions.x.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  data.positions.y.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  for (std::size_t p = 0; p < pixels; ++p) {
    const std::size_t o = obs.At(int(p), 0);
    const float* rgb = &obs.rgb[3 * o];
    // As the solver: an observation counts only with all three channels.
    if (map.Plane("valid", int(p % w), int(p / w)) == 0 ||
        !(std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2])))
      continue;
    const double cos_in = std::max(double(obs.light[o].z()), 0.0);
    for (int ch = 0; ch < 3; ++ch) {
      data.captured[3 * p + ch] = float(rgb[ch] * cos_in);
      data.light[3 * p + ch] = obs.light[o][ch];
      data.camera[3 * p + ch] = obs.camera[o][ch];
    }
    data.compared[p] = 1;
    data.positions.x[p] = view_x[p];
    data.positions.y[p] = view_y[p];
  }
  return data;
}

RgbImage PredictAtPixels(const ValidationData& data, const PixelBrdf& brdf) {
  const int w = data.width, h = data.height;
  RgbImage predicted{w, h, std::vector<float>(std::size_t(w) * std::size_t(h) * 3, 0.0f)};
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      if (!data.compared[p]) continue;
      const Eigen::Vector3d in(data.light[3 * p], data.light[3 * p + 1], data.light[3 * p + 2]);
      const Eigen::Vector3d out(data.camera[3 * p], data.camera[3 * p + 1], data.camera[3 * p + 2]);
      const auto rho = brdf(x, y, in, out);
      const double cos_in = std::max(in.z(), 0.0);
      for (int ch = 0; ch < 3; ++ch) predicted.rgb[3 * p + ch] = float(rho[ch] * cos_in);
    }
  return predicted;
}

ValidationResult Compare(const ValidationData& data, const PixelBrdf& brdf) {
  return Compare(data, PredictAtPixels(data, brdf));
}

ValidationResult Compare(const ValidationData& data, const RgbImage& at_pixels) {
  const int w = data.width, h = data.height;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  if (at_pixels.rgb.size() != 3 * pixels)
    throw std::invalid_argument("Compare: a prediction of another size than the view's data");
  ValidationResult result;
  result.name = data.name;
  result.predicted = at_pixels;
  if (!data.positions.empty())
    result.predicted.rgb = SampleAsCaptured(w, h, data.positions, at_pixels.rgb, data.compared);
  result.captured = {w, h, std::vector<float>(pixels * 3, 0.0f)};
  for (std::size_t p = 0; p < pixels; ++p)
    if (data.compared[p])
      for (int ch = 0; ch < 3; ++ch) result.captured.rgb[3 * p + ch] = data.captured[3 * p + ch];
  double diff2 = 0, ref2 = 0, worst2 = 0;
  std::vector<double> relative, delta_e;
  constexpr double kPi = 3.14159265358979323846;
  for (std::size_t p = 0; p < pixels; ++p) {
    if (!data.compared[p]) continue;
    double pixel2 = 0;
    for (int ch = 0; ch < 3; ++ch) {
      const double a = result.predicted.rgb[3 * p + ch], b = result.captured.rgb[3 * p + ch];
      pixel2 += (a - b) * (a - b);
      ref2 += b * b;
      if (b > 0) relative.push_back(std::abs(a - b) / b);
    }
    diff2 += pixel2;
    if (pixel2 > worst2) {
      worst2 = pixel2;
      result.worst_x = int(p % std::size_t(w)), result.worst_y = int(p / std::size_t(w));
    }
    const float* a = &result.predicted.rgb[3 * p];
    const float* b = &result.captured.rgb[3 * p];
    delta_e.push_back(DeltaE2000(LabFromLinearRec709({kPi * a[0], kPi * a[1], kPi * a[2]}),
                                 LabFromLinearRec709({kPi * b[0], kPi * b[1], kPi * b[2]})));
    ++result.pixels;
  }
  result.median_delta_e2000 = delta_e.empty() ? 0 : Median(delta_e);
  result.relative_rms = ref2 > 0 ? std::sqrt(diff2 / ref2) : 0;
  result.worst_share = diff2 > 0 ? worst2 / diff2 : 0;
  result.median_relative = relative.empty() ? 0 : Median(relative);
  return result;
}

std::vector<double> RelativeRmsByLabel(const ValidationResult& result,
                                       const std::vector<int>& labels, std::size_t count) {
  if (labels.size() * 3 != result.captured.rgb.size() ||
      result.predicted.rgb.size() != result.captured.rgb.size())
    throw std::invalid_argument("RelativeRmsByLabel: labels and images of different sizes");
  std::vector<double> diff2(count, 0), ref2(count, 0);
  for (std::size_t p = 0; p < labels.size(); ++p) {
    if (labels[p] < 0 || std::size_t(labels[p]) >= count) continue;
    for (int ch = 0; ch < 3; ++ch) {  // pixels not compared are 0 in both images
      const double a = result.predicted.rgb[3 * p + ch], b = result.captured.rgb[3 * p + ch];
      diff2[std::size_t(labels[p])] += (a - b) * (a - b);
      ref2[std::size_t(labels[p])] += b * b;
    }
  }
  std::vector<double> out;
  for (std::size_t m = 0; m < count; ++m)
    out.push_back(ref2[m] > 0 ? std::sqrt(diff2[m] / ref2[m]) : 0.0);
  return out;
}

ValidationResult CompareWithCapture(const SvbrdfMap& map, const BasisView& basis, SessionView view,
                                    RowLookup lookup) {
  return Compare(CaptureOfView(map, std::move(view)), MapPixelBrdf(map, basis, lookup));
}

namespace {

constexpr const char* kValidationPlanes[3][3] = {{"captured.R", "captured.G", "captured.B"},
                                                 {"light.x", "light.y", "light.z"},
                                                 {"camera.x", "camera.y", "camera.z"}};
constexpr const char* kPredictedPlanes[3] = {"predicted.R", "predicted.G", "predicted.B"};
constexpr const char* kPositionPlanes[2] = {"view.x", "view.y"};

}  // namespace

void WriteValidationData(const ValidationData& data, const std::string& path,
                         const RgbImage* predicted) {
  FloatPlanes f;
  f.width = data.width;
  f.height = data.height;
  const std::size_t pixels = std::size_t(data.width) * std::size_t(data.height);
  const std::vector<float>* sources[3] = {&data.captured, &data.light, &data.camera};
  for (int s = 0; s < 3; ++s)
    for (int c = 0; c < 3; ++c) {
      std::vector<float>& plane = f.planes[kValidationPlanes[s][c]];
      plane.resize(pixels);
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = (*sources[s])[3 * p + c];
    }
  std::vector<float>& compared = f.planes["compared"];
  compared.assign(data.compared.begin(), data.compared.end());
  if (!data.positions.empty()) {
    f.planes[kPositionPlanes[0]] = data.positions.x;
    f.planes[kPositionPlanes[1]] = data.positions.y;
  }
  if (predicted && predicted->rgb.size() == 3 * pixels)
    for (int c = 0; c < 3; ++c) {
      std::vector<float>& plane = f.planes[kPredictedPlanes[c]];
      plane.resize(pixels);
      for (std::size_t p = 0; p < pixels; ++p) plane[p] = predicted->rgb[3 * p + std::size_t(c)];
    }
  f.attributes["acqValidationView"] = data.name;
  WriteFloatPlanesExr(path, f);
}

ValidationData ReadValidationData(const std::string& path) {
  const FloatPlanes f = ReadFloatPlanesExr(path);
  ValidationData data;
  const auto name = f.attributes.find("acqValidationView");
  if (name == f.attributes.end())
    throw UserError(path, "is not a validation view's data (no acqValidationView attribute)",
                    "give a renders/validation_NNN.exr written by the session's processing");
  data.name = name->second;
  data.width = f.width;
  data.height = f.height;
  const std::size_t pixels = std::size_t(f.width) * std::size_t(f.height);
  std::vector<float>* targets[3] = {&data.captured, &data.light, &data.camera};
  for (int s = 0; s < 3; ++s) {
    targets[s]->resize(3 * pixels);
    for (int c = 0; c < 3; ++c) {
      const std::vector<float>& plane = f.Plane(kValidationPlanes[s][c], path);
      for (std::size_t p = 0; p < pixels; ++p) (*targets[s])[3 * p + c] = plane[p];
    }
  }
  const std::vector<float>& compared = f.Plane("compared", path);
  data.compared.resize(pixels);
  for (std::size_t p = 0; p < pixels; ++p) data.compared[p] = compared[p] > 0.5f;
  // Data kept before the positions were kept are compared at the pixels' own points.
  if (f.planes.count(kPositionPlanes[0]) && f.planes.count(kPositionPlanes[1]))
    data.positions = {f.Plane(kPositionPlanes[0], path), f.Plane(kPositionPlanes[1], path)};
  return data;
}

}  // namespace acq
