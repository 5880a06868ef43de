#include "sim/relief.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/angles.h"
#include "core/error.h"
#include "core/facet_frame.h"
#include "core/sample_grid.h"
#include "io/float_planes_exr.h"
#include "sim/sample_files.h"

namespace acq::sim {
namespace {

// Separable Gaussian blur of a w x h image, edges clamped.
std::vector<float> Blur(const std::vector<float>& in, int w, int h, double sigma) {
  const int r = std::max(1, int(std::ceil(3 * sigma)));
  std::vector<float> kernel(2 * r + 1);
  float sum = 0;
  for (int i = -r; i <= r; ++i)
    sum += kernel[i + r] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
  for (float& k : kernel) k /= sum;
  std::vector<float> tmp(in.size()), out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i)
        s += kernel[i + r] * in[std::size_t(y) * w + std::clamp(x + i, 0, w - 1)];
      tmp[std::size_t(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i)
        s += kernel[i + r] * tmp[std::size_t(std::clamp(y + i, 0, h - 1)) * w + x];
      out[std::size_t(y) * w + x] = s;
    }
  return out;
}

// The gradient of a height map at (x, y): central differences, one-sided at the edges.
Eigen::Vector2f Gradient(const std::vector<float>& h, int w, int ht, int x, int y) {
  auto at = [&](int xx, int yy) { return h[std::size_t(yy) * w + xx]; };
  const int x0 = std::max(0, x - 1), x1 = std::min(w - 1, x + 1);
  const int y0 = std::max(0, y - 1), y1 = std::min(ht - 1, y + 1);
  return {x1 > x0 ? (at(x1, y) - at(x0, y)) / float(x1 - x0) : 0.0f,
          y1 > y0 ? (at(x, y1) - at(x, y0)) / float(y1 - y0) : 0.0f};
}

// Scales `h` so that its steepest slope (or its RMS slope) is tan(slope).
void ScaleSlope(std::vector<float>* h, int w, int ht, double slope_rad, bool rms) {
  double steepest = 0, sum = 0;
  for (int y = 0; y < ht; ++y)
    for (int x = 0; x < w; ++x) {
      const double g = Gradient(*h, w, ht, x, y).norm();
      steepest = std::max(steepest, g);
      sum += g * g;
    }
  const double measure = rms ? std::sqrt(sum / double(std::size_t(w) * ht)) : steepest;
  const float scale = measure > 0 ? float(std::tan(slope_rad) / measure) : 0.0f;
  for (float& v : *h) v *= scale;
}

}  // namespace

void ReliefOptions::Check() const {
  if (!(slope_deg >= 0 && slope_deg < 60))
    throw UserError("--relief-deg", "must be in [0, 60) degrees", "the issue's study uses 2 to 20");
  if (!(fibre_deg >= 0 && fibre_deg < 30)) throw UserError("--fibre-deg", "must be in [0, 30)");
  if (!(edge_px > 0)) throw UserError("relief edge", "must be positive");
}

std::vector<float> CardRelief(const SyntheticSvbrdf& layout, const ReliefOptions& o) {
  o.Check();
  const int w = layout.width, h = layout.height;
  std::vector<float> mask(std::size_t(w) * h, 0.0f);
  const int border = std::max(1, int(std::lround(o.border_share * std::min(w, h))));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool in_border = x < border || y < border || x >= w - border || y >= h - border;
      mask[std::size_t(y) * w + x] = in_border || layout.label[std::size_t(y) * w + x] != 0;
    }
  std::vector<float> height = Blur(mask, w, h, o.edge_px);
  ScaleSlope(&height, w, h, DegToRad(o.slope_deg), false);
  if (o.fibre_deg > 0) {
    std::mt19937_64 rng(o.seed * 0x9E3779B97F4A7C15ull + 19);
    std::normal_distribution<float> white(0.0f, 1.0f);
    std::vector<float> fibre(height.size());
    for (float& v : fibre) v = white(rng);
    fibre = Blur(fibre, w, h, 1.0);
    ScaleSlope(&fibre, w, h, DegToRad(o.fibre_deg), true);
    for (std::size_t i = 0; i < height.size(); ++i) height[i] += fibre[i];
  }
  return height;
}

std::vector<float> ReadHeightMap(const std::string& path, int width, int height,
                                 double png_height_px) {
  std::vector<float> out;
  int w = 0, h = 0;
  if (path.size() > 4 && path.substr(path.size() - 4) == ".exr") {
    FloatPlanes file = ReadFloatPlanesExr(path);
    if (!file.planes.count("height"))
      throw UserError(path, "has no 'height' plane", "write the heights (in pixels) as 'height'");
    w = file.width, h = file.height;
    out = std::move(file.planes["height"]);
  } else {
    const cv::Mat grey = ReadGreyImage(
        path, "height map", "give an EXR with a 'height' plane or an 8- or 16-bit grey PNG");
    w = grey.cols, h = grey.rows;
    const double full = grey.depth() == CV_16U ? 65535.0 : 255.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        out.push_back(float(
            (grey.depth() == CV_16U ? grey.at<std::uint16_t>(y, x) : grey.at<std::uint8_t>(y, x)) /
            full * png_height_px));
  }
  if (w != width || h != height)
    throw UserError(path,
                    "the height map is " + std::to_string(w) + "x" + std::to_string(h) +
                        ", the sample " + std::to_string(width) + "x" + std::to_string(height),
                    "give a height map of the sample's size");
  for (std::size_t p = 0; p < out.size(); ++p)
    if (!std::isfinite(out[p]))
      throw UserError(path, PixelName(p, w) + " has a height that is not finite",
                      "give finite heights, in pixels");
  return out;
}

void SetNormalsFromHeight(SyntheticSvbrdf* layout, const std::vector<float>& height) {
  const int w = layout->width, h = layout->height;
  layout->normal.resize(std::size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector2f g = Gradient(height, w, h, x, y);
      const Eigen::Vector2d slope = SampleGrid::SlopeOf(g.x(), g.y());
      layout->normal[std::size_t(y) * w + x] = NormalOfSlope(-float(slope.x()), -float(slope.y()));
    }
}

}  // namespace acq::sim
