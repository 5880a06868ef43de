#include "export/pbr_textures.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "core/colour.h"
#include "core/error.h"
#include "io/float_planes_exr.h"

namespace acq {
namespace {

std::uint8_t Byte(double v) {
  return std::uint8_t(std::clamp(v, 0.0, 1.0) * 255 + 0.5);
}

void Write(const cv::Mat& image, const std::string& path) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw UserError(path, "could not be written", "check the folder and the free space");
}

// An 8-bit BGR image from a function of the pixel giving linear or encoded RGB in [0, 1].
template <typename F>
cv::Mat Image(const PbrMaps& maps, F rgb) {
  cv::Mat out(maps.height, maps.width, CV_8UC3);
  for (int y = 0; y < maps.height; ++y)
    for (int x = 0; x < maps.width; ++x) {
      const std::array<double, 3> v = rgb(std::size_t(y) * maps.width + x);
      out.at<cv::Vec3b>(y, x) = cv::Vec3b(Byte(v[2]), Byte(v[1]), Byte(v[0]));
    }
  return out;
}

// An 8-bit grey image with alpha, every channel the pixel's value in [0, 1].
template <typename F>
cv::Mat GreyWithAlpha(const PbrMaps& maps, F value) {
  cv::Mat out(maps.height, maps.width, CV_8UC4);
  for (int y = 0; y < maps.height; ++y)
    for (int x = 0; x < maps.width; ++x) {
      const std::uint8_t v = Byte(value(std::size_t(y) * maps.width + x));
      out.at<cv::Vec4b>(y, x) = cv::Vec4b(v, v, v, v);
    }
  return out;
}

std::array<double, 3> Srgb(const std::array<double, 3>& linear) {
  return {SrgbEncode(linear[0]), SrgbEncode(linear[1]), SrgbEncode(linear[2])};
}

}  // namespace

PbrTextureSet WritePbrTextures(const PbrMaps& maps, const std::string& dir) {
  using N = PbrTextureNames;
  PbrTextureSet set;
  Write(Image(maps, [&](std::size_t p) { return Srgb(maps.parameters[p].diffuse); }),
        dir + "/" + N::kBaseColor);
  Write(Image(maps,
              [&](std::size_t p) {
                return std::array<double, 3>{1.0, maps.parameters[p].roughness, 0.0};
              }),
        dir + "/" + N::kMetallicRoughness);
  Write(Image(maps, [&](std::size_t p) { return Srgb(maps.parameters[p].f0); }),
        dir + "/" + N::kSpecular);
  Write(GreyWithAlpha(maps, [&](std::size_t p) { return maps.parameters[p].specular; }),
        dir + "/" + N::kSpecularWeight);
  set.coat = std::any_of(maps.parameters.begin(), maps.parameters.end(),
                         [](const PbrParameters& p) { return p.coat > 0; });
  if (set.coat)
    Write(Image(maps,
                [&](std::size_t p) {
                  const PbrParameters& q = maps.parameters[p];
                  return std::array<double, 3>{q.coat, q.coat_roughness, 0.0};
                }),
          dir + "/" + N::kCoat);
  Write(Image(maps,
              [&](std::size_t p) {
                const double r = maps.parameters[p].roughness;
                return std::array<double, 3>{r, r, r};
              }),
        dir + "/" + N::kRoughness);

  FloatPlanes error;
  error.width = maps.width;
  error.height = maps.height;
  error.planes["log_rmse"] = maps.log_rmse;
  error.planes["converged"].assign(maps.converged.begin(), maps.converged.end());
  error.planes["valid"].assign(maps.valid.begin(), maps.valid.end());
  error.attributes["meaning"] =
      "the analytic fit's RMS log-space error against the map's BRDF per pixel; converged 0: "
      "the fit did not converge (its parameters are the best it reached)";
  WriteFloatPlanesExr(dir + "/" + N::kFitError, error);

  std::vector<float> sorted = maps.log_rmse;
  double top = 0;
  if (!sorted.empty()) {
    const std::size_t at = std::size_t(0.99 * double(sorted.size() - 1));
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(at), sorted.end());
    top = sorted[at];
  }
  Write(Image(maps,
              [&](std::size_t p) {
                if (!maps.converged[p]) return std::array<double, 3>{1, 0, 0};
                const double v = top > 0 ? maps.log_rmse[p] / top : 0;
                return std::array<double, 3>{v, v, v};
              }),
        dir + "/" + N::kFitErrorPng);
  return set;
}

}  // namespace acq
