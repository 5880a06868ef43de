#include "acq/map_render.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "acq/height_from_normals.h"
#include "brdf/normal_search.h"
#include "brdf/pooled_model.h"
#include "core/angles.h"
#include "core/colour.h"
#include "core/error.h"
#include "core/facet_frame.h"
#include "core/sample_grid.h"
#include "io/float_planes_exr.h"

namespace acq {
namespace {

// Sample point of a reference pixel: the reference view looks straight down at the centre.
Eigen::Vector2d PointOf(const SvbrdfMap& map, int x, int y) {
  const SampleGrid grid{map.info.width, map.info.height, map.info.width * map.info.pixel_size_mm,
                        map.info.height * map.info.pixel_size_mm};
  return grid.CentreOf(x, y);
}

void CheckBasis(const SvbrdfMap& map, const BasisView& basis) {
  if (basis.components < map.info.components)
    throw UserError("--basis",
                    "the basis has " + std::to_string(basis.components) +
                        " components, the map needs " + std::to_string(map.info.components),
                    "give the basis the map was reconstructed with (" + map.info.basis + ")");
}

}  // namespace

std::vector<float> PixelCoefficients(const SvbrdfMap& map, int x, int y) {
  std::vector<float> all;
  for (int c = 0; c < 3; ++c) {
    const std::vector<float> v = map.Coefficients(x, y, c);
    all.insert(all.end(), v.begin(), v.end());
  }
  return all;
}

namespace {

// The slope (n.x / n.z, n.y / n.z) of the normal the map renders pixel (x, y) with (the sample's
// unless estimated); pixels past the map's edge take the edge's.
Eigen::Vector2f RenderedSlope(const SvbrdfMap& map, int x, int y) {
  x = std::clamp(x, 0, map.info.width - 1);
  y = std::clamp(y, 0, map.info.height - 1);
  if (map.Plane("normal_status", x, y) != float(NormalStatus::kEstimated)) return {0, 0};
  const float nz = map.Plane("normal.z", x, y);
  return {map.Plane("normal.x", x, y) / nz, map.Plane("normal.y", x, y) / nz};
}

// A camera pixel's spread as a box of the same variance: half-width sqrt(3) x spread (for a
// whole pixel, its edges), read at the midpoints of equal parts along each axis. The parts
// follow how far the normal turns across the box, at most kTurnPerPartDeg each: a mirror-like
// ink's peak is a degree or two wide (brass's falls from 155 to 5.6 within 1.7 degrees), so a
// rule of a few fixed points under- or overshoots it by several times where the normal turns as
// much across a pixel.
constexpr double kSpreadToHalfWidth = 1.7320508075688772;  // sqrt(3)
constexpr double kTurnPerPartDeg = 0.25;
// Past this turn across the box along either axis the pixel is rendered at its own normal. Its
// neighbours' normals then lie several degrees a pixel apart: a steep edge, where the search
// refuses or takes back normals (the sample's normal stands in for an unknown one) and the
// normals it keeps are least sure; a box over them reaches highlights of normals no facet of the
// footprint has (docs/reconstruction.md, "A camera pixel's footprint in the map's renders").
constexpr double kMaxTurnAcrossDeg = 4;  // 16 parts a side at most

// The parts along one axis of the box for the slope's change across it; 0 past the limit.
int PartsAcross(const Eigen::Vector2f& slope_change) {
  const double turn_deg = std::atan(double(slope_change.norm())) * 180 / kPi;
  if (turn_deg > kMaxTurnAcrossDeg) return 0;
  return std::max(1, int(std::ceil(turn_deg / kTurnPerPartDeg)));
}

}  // namespace

std::array<double, 3> MapBrdfAt(const SvbrdfMap& map, const BasisView& basis, int x, int y,
                                const Eigen::Vector3d& in, const Eigen::Vector3d& out,
                                RowLookup lookup) {
  const std::vector<float> c = PixelCoefficients(map, x, y);
  const auto facet = [&](const Eigen::Vector3d& fi, const Eigen::Vector3d& fo) {
    return BrdfFromCoefficients(basis, c.data(), map.info.components, fi, fo, lookup);
  };
  Eigen::Vector2f along_x = Eigen::Vector2f::Zero(), along_y = Eigen::Vector2f::Zero();
  if (map.info.pixel_spread_px > 0) {  // the slope's change a pixel, by central differences
    along_x = (RenderedSlope(map, x + 1, y) - RenderedSlope(map, x - 1, y)) / 2;
    along_y = (RenderedSlope(map, x, y + 1) - RenderedSlope(map, x, y - 1)) / 2;
  }
  const float half = float(kSpreadToHalfWidth * map.info.pixel_spread_px);
  const int nx = PartsAcross(2 * half * along_x), ny = PartsAcross(2 * half * along_y);
  if (nx * ny <= 1) {  // one normal over the whole pixel
    if (map.Plane("normal_status", x, y) != float(NormalStatus::kEstimated)) return facet(in, out);
    const Eigen::Vector3f n(map.Plane("normal.x", x, y), map.Plane("normal.y", x, y),
                            map.Plane("normal.z", x, y));
    return SeenAsFlat(n.normalized(), in, out, facet);
  }
  // The camera's pixel integrated over points spread about its centre, across which the normal
  // changes as its neighbours' do: the mean over that box, by the rule above.
  const Eigen::Vector2f slope = RenderedSlope(map, x, y);
  std::array<double, 3> mean{0, 0, 0};
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const float u = half * (2 * (i + 0.5f) / nx - 1), v = half * (2 * (j + 0.5f) / ny - 1);
      const Eigen::Vector2f s = slope + u * along_x + v * along_y;
      const std::array<double, 3> value = SeenAsFlat(NormalOfSlope(s.x(), s.y()), in, out, facet);
      for (int ch = 0; ch < 3; ++ch) mean[ch] += value[ch] / (nx * ny);
    }
  return mean;
}

RgbImage RenderView(const SvbrdfMap& map, const BasisView& basis, const ArmAngles& arms,
                    const NearFieldGeometry& geometry, RowLookup lookup) {
  CheckBasis(map, basis);
  RgbImage img{map.info.width, map.info.height,
               std::vector<float>(std::size_t(map.info.width) * map.info.height * 3, 0.0f)};
  const DirectionPair far = DirectionsOf(arms);
  const Eigen::Vector3d light_pos = geometry.light_distance_mm * far.in;
#pragma omp parallel for schedule(dynamic, 8)
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const Eigen::Vector2d p = PointOf(map, x, y);
      const DirectionPair d = geometry.DirectionsAt(far, p);
      const double r_m = (light_pos - Eigen::Vector3d(p.x(), p.y(), 0)).norm() / 1000.0;
      const auto rho = MapBrdfAt(map, basis, x, y, d.in, d.out, lookup);
      for (int ch = 0; ch < 3; ++ch)
        img.rgb[(std::size_t(y) * img.width + x) * 3 + ch] =
            float(rho[ch] * std::max(d.in.z(), 0.0) / (r_m * r_m));
    }
  }
  return img;
}

RgbImage RenderConfiguration(const SvbrdfMap& map, const BasisView& basis, const DirectionPair& d,
                             RowLookup lookup) {
  CheckBasis(map, basis);
  RgbImage img{map.info.width, map.info.height,
               std::vector<float>(std::size_t(map.info.width) * map.info.height * 3, 0.0f)};
#pragma omp parallel for schedule(dynamic, 8)
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const auto rho = MapBrdfAt(map, basis, x, y, d.in, d.out, lookup);
      for (int ch = 0; ch < 3; ++ch)
        img.rgb[(std::size_t(y) * img.width + x) * 3 + ch] = float(rho[ch]);
    }
  return img;
}

RgbImage RenderSpheres(const SvbrdfMap& map, const BasisView& basis,
                       const std::vector<std::pair<int, int>>& pixels, const Eigen::Vector3d& light,
                       int size, RowLookup lookup) {
  CheckBasis(map, basis);
  RgbImage img{size * int(pixels.size()), size,
               std::vector<float>(std::size_t(size) * size * pixels.size() * 3, 0.0f)};
  const Eigen::Vector3d view(0, 0, 1), l = light.normalized();
  for (std::size_t s = 0; s < pixels.size(); ++s) {
    const auto [px, py] = pixels[s];
    if (px < 0 || py < 0 || px >= map.info.width || py >= map.info.height)
      throw UserError("--pixel " + std::to_string(px) + "," + std::to_string(py),
                      "outside the map (" + std::to_string(map.info.width) + "x" +
                          std::to_string(map.info.height) + ")");
    const std::vector<float> c = PixelCoefficients(map, px, py);
#pragma omp parallel for schedule(dynamic, 4)
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const double u = (x + 0.5) / size * 2 - 1, v = 1 - (y + 0.5) / size * 2;
        if (u * u + v * v >= 1) continue;
        const Eigen::Vector3d n(u, v, std::sqrt(1 - u * u - v * v));
        // Local frame at the sphere point: z along the normal.
        const Eigen::Vector3d t =
            (std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY())
                .cross(n)
                .normalized();
        const Eigen::Vector3d b = n.cross(t);
        const Eigen::Vector3d in(l.dot(t), l.dot(b), l.dot(n)),
            out(view.dot(t), view.dot(b), view.dot(n));
        if (in.z() <= 0 || out.z() <= 0) continue;
        const auto rho =
            BrdfFromCoefficients(basis, c.data(), map.info.components, in, out, lookup);
        for (int ch = 0; ch < 3; ++ch)
          img.rgb[(std::size_t(y) * img.width + s * size + x) * 3 + ch] = float(rho[ch] * in.z());
      }
  }
  return img;
}

MerlBrdf PixelAsMerl(const SvbrdfMap& map, const BasisView& basis, int x, int y) {
  CheckBasis(map, basis);
  if (x < 0 || y < 0 || x >= map.info.width || y >= map.info.height)
    throw UserError("--pixel " + std::to_string(x) + "," + std::to_string(y), "outside the map");
  const std::vector<float> c = PixelCoefficients(map, x, y);
  MerlBrdf out;
  const merl::GridGeometry& g = merl::Geometry();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < g.valid_bins.size(); ++i) {
    const std::uint32_t bin = g.valid_bins[i];
    const DirectionPair d = DirectionsFromRusinkiewicz(merl::BinCentre(merl::BinFromFlat(bin)));
    const auto rho = BrdfFromCoefficients(basis, c.data(), map.info.components, d.in, d.out,
                                          RowLookup::kNearest);
    for (int ch = 0; ch < 3; ++ch) out.SetValue(ch, bin, rho[ch]);
  }
  return out;
}

RowLookup MapRowLookup(const SvbrdfMap& map) {
  return ParseRowLookup(map.info.lookup).value_or(RowLookup::kNearest);
}

double AutoExposure(std::vector<float> v) {
  if (v.empty()) return 1.0;
  const std::size_t at = std::min(v.size() - 1, std::size_t(0.99 * double(v.size())));
  std::nth_element(v.begin(), v.begin() + at, v.end());
  return v[at] > 0 ? 0.9 / v[at] : 1.0;
}

void WritePng(const RgbImage& image, const std::string& path, double exposure) {
  if (exposure <= 0) exposure = AutoExposure(image.rgb);
  cv::Mat out(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        const double srgb =
            SrgbEncode(image.rgb[(std::size_t(y) * image.width + x) * 3 + ch] * exposure);
        out.at<cv::Vec3b>(y, x)[2 - ch] = cv::saturate_cast<uchar>(srgb * 255 + 0.5);  // BGR
      }
  bool ok = false;
  try {
    ok = cv::imwrite(path, out);
  } catch (const cv::Exception& e) {
    throw UserError(path, std::string("cannot write PNG: ") + e.what());
  }
  if (!ok)
    throw UserError(path, "cannot write PNG", "check the folder exists and the name ends in .png");
}

namespace {

// The pooled map's groups, one colour each (hues a golden angle apart), black for pixels solved
// alone.
void WriteGroupPng(const SvbrdfMap& map, const std::string& path) {
  cv::Mat hsv(map.info.height, map.info.width, CV_8UC3);
  for (int y = 0; y < map.info.height; ++y)
    for (int x = 0; x < map.info.width; ++x) {
      const int g = int(map.Plane("group", x, y));
      hsv.at<cv::Vec3b>(y, x) =
          g < 0 ? cv::Vec3b(0, 0, 0)
                : cv::Vec3b(uchar(int(g * 137.508 / 2) % 180), uchar(g % 2 ? 160 : 255), 255);
    }
  cv::Mat bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  if (!cv::imwrite(path, bgr)) throw UserError(path, "cannot write PNG");
}

}  // namespace

bool HasEstimatedNormals(const SvbrdfMap& map) {
  for (int y = 0; y < map.info.height; ++y)
    for (int x = 0; x < map.info.width; ++x)
      if (map.Plane("normal_status", x, y) != 0) return true;
  return false;
}

// The normal map in the usual colour convention: (n + 1) / 2 as R, G, B, 8 bits, no gamma
// (flat is (128, 128, 255)).
void WriteNormalPng(const SvbrdfMap& map, const std::string& path) {
  cv::Mat out(map.info.height, map.info.width, CV_8UC3);
  for (int y = 0; y < map.info.height; ++y)
    for (int x = 0; x < map.info.width; ++x) {
      const char* axes[3] = {"normal.x", "normal.y", "normal.z"};
      for (int a = 0; a < 3; ++a)
        out.at<cv::Vec3b>(y, x)[2 - a] =
            cv::saturate_cast<uchar>((map.Plane(axes[a], x, y) + 1.0) * 127.5);  // BGR
    }
  if (!cv::imwrite(path, out)) throw UserError(path, "cannot write PNG");
}

// The height integrated from the normals (height_from_normals.h) in grey, lowest black, highest
// white, 8 bits linear: a relief's shape at a glance; its scale is in the map's normals.
void WriteHeightPng(const SvbrdfMap& map, const std::string& path) {
  const int w = map.info.width, h = map.info.height;
  std::vector<Eigen::Vector3f> normals(std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      normals[std::size_t(y) * w + x] = {map.Plane("normal.x", x, y), map.Plane("normal.y", x, y),
                                         map.Plane("normal.z", x, y)};
  const std::vector<float> height = HeightFromNormals(normals, w, h);
  const auto [lo, hi] = std::minmax_element(height.begin(), height.end());
  const double range = *hi - *lo;
  cv::Mat out(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      out.at<uchar>(y, x) = cv::saturate_cast<uchar>(
          range > 0 ? (height[std::size_t(y) * w + x] - *lo) / range * 255 : 128);
  if (!cv::imwrite(path, out)) throw UserError(path, "cannot write PNG");
}

// Each estimated normal's uncertainty (normal_uncertainty_deg) in viridis, on a log scale from
// the finest step in the map (dark) to the largest (yellow): the search's steps halve, so each
// step is one band of colour. Black where no normal was estimated.
void WriteNormalUncertaintyPng(const SvbrdfMap& map, const std::string& path) {
  const int w = map.info.width, h = map.info.height;
  cv::Mat radius(h, w, CV_32FC1);
  float finest = std::numeric_limits<float>::infinity(), largest = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float u = radius.at<float>(y, x) = map.Plane("normal_uncertainty_deg", x, y);
      if (u > 0) finest = std::min(finest, u);
      largest = std::max(largest, u);
    }
  const bool graded = std::isfinite(finest);  // some pixel's uncertainty above 0
  const double scale = graded ? std::log1p(largest / finest) : 1;
  cv::Mat level(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      level.at<uchar>(y, x) = cv::saturate_cast<uchar>(
          graded ? 255 * std::log1p(std::max(radius.at<float>(y, x), 0.0f) / finest) / scale : 0);
  cv::Mat out;
  cv::applyColorMap(level, out, cv::COLORMAP_VIRIDIS);
  out.setTo(cv::Scalar(0, 0, 0), radius < 0);  // none estimated
  if (!cv::imwrite(path, out)) throw UserError(path, "cannot write PNG");
}

void WriteRgbExr(const RgbImage& image, const std::string& path) {
  FloatPlanes planes;
  planes.width = image.width;
  planes.height = image.height;
  const char* names[3] = {"R", "G", "B"};
  const std::size_t pixels = std::size_t(image.width) * std::size_t(image.height);
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& plane = planes.planes[names[c]];
    plane.resize(pixels);
    for (std::size_t p = 0; p < pixels; ++p) plane[p] = image.rgb[3 * p + c];
  }
  WriteFloatPlanesExr(path, planes);
}

void WriteDiagnosticPng(const SvbrdfMap& map, const std::string& plane, const std::string& path) {
  if (plane == "group") return WriteGroupPng(map, path);
  const bool log_scale = plane == "condition";
  std::vector<double> v;
  for (int y = 0; y < map.info.height; ++y)
    for (int x = 0; x < map.info.width; ++x) {
      double a = map.Plane(plane, x, y);
      if (log_scale) a = std::isfinite(a) && a > 0 ? std::log10(a) : 8.0;  // inf shown as 1e8
      v.push_back(a);
    }
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  const double span = *hi - *lo;
  cv::Mat out(map.info.height, map.info.width, CV_8UC1);
  // A plane of one value (every pixel valid, say) has no range: white where it is positive.
  for (int i = 0; i < int(v.size()); ++i)
    out.at<uchar>(i / map.info.width, i % map.info.width) =
        cv::saturate_cast<uchar>(span > 0 ? (v[i] - *lo) / span * 255 : (v[i] > 0 ? 255 : 0));
  if (!cv::imwrite(path, out)) throw UserError(path, "cannot write PNG");
}

std::vector<std::string> WriteQuickLooks(const SvbrdfMap& map, const BasisView& basis,
                                         const std::string& dir, const std::string& prefix) {
  const RowLookup lookup = MapRowLookup(map);
  // Diffuse-looking: light 45 degrees off, camera overhead, far from the mirror direction.
  const ArmAngles diffuse{DegToRad(45), 0, 0, 0};
  // Specular: light and camera mirrored at 30 degrees (theta_h = 0).
  const ArmAngles specular{DegToRad(30), 0, DegToRad(30), kPi};
  const std::string stem = dir + "/" + prefix;
  WritePng(RenderConfiguration(map, basis, DirectionsOf(diffuse), lookup), stem + "diffuse.png");
  WritePng(RenderConfiguration(map, basis, DirectionsOf(specular), lookup), stem + "specular.png");
  std::vector<std::string> names = {"diffuse", "specular"};
  std::vector<std::string> planes = {"valid", "observations", "condition", "residual"};
  if (map.info.method == ReconstructionMethodName(ReconstructionMethod::kPooled))
    planes.insert(planes.end(), {"group", "departure"});
  for (const std::string& plane : planes) {
    WriteDiagnosticPng(map, plane, stem + plane + ".png");
    names.push_back(plane);
  }
  if (HasEstimatedNormals(map)) {
    WriteNormalPng(map, stem + "normal.png");
    WriteHeightPng(map, stem + "height.png");
    WriteNormalUncertaintyPng(map, stem + "normal_uncertainty.png");
    names.insert(names.end(), {"normal", "height", "normal_uncertainty"});
  }
  return names;
}

}  // namespace acq
