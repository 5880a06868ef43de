#include "acq/demosaic.h"

#include <algorithm>
#include <stdexcept>

namespace acq {
namespace {

// Malvar-He-Cutler kernels, in eighths, 5 x 5 row by row (their Fig. 2).
using Kernel = float[5][5];
constexpr Kernel kGreenAtRedOrBlue = {
    {0, 0, -1, 0, 0}, {0, 0, 2, 0, 0}, {-1, 2, 4, 2, -1}, {0, 0, 2, 0, 0}, {0, 0, -1, 0, 0}};
// At a green photosite, the channel of its row's other photosites (and, transposed, its column's).
constexpr Kernel kRowChannelAtGreen = {{0, 0, 0.5f, 0, 0},
                                       {0, -1, 0, -1, 0},
                                       {-1, 4, 5, 4, -1},
                                       {0, -1, 0, -1, 0},
                                       {0, 0, 0.5f, 0, 0}};
constexpr Kernel kColumnChannelAtGreen = {{0, 0, -1, 0, 0},
                                          {0, -1, 4, -1, 0},
                                          {0.5f, 0, 5, 0, 0.5f},
                                          {0, -1, 4, -1, 0},
                                          {0, 0, -1, 0, 0}};
// Red at a blue photosite, or blue at a red one.
constexpr Kernel kOppositeAtRedOrBlue = {{0, 0, -1.5f, 0, 0},
                                         {0, 2, 0, 2, 0},
                                         {-1.5f, 0, 6, 0, -1.5f},
                                         {0, 2, 0, 2, 0},
                                         {0, 0, -1.5f, 0, 0}};

struct Mosaic {
  const HdrImage& image;
  int At(int x, int y) const { return CfaChannel(image.cfa, x, y); }
  // Reflected at the borders (x = -1 reads x = 1), which keeps the filter's phase.
  float Value(int x, int y) const {
    const int w = image.width, h = image.height;
    x = x < 0 ? -x : (x >= w ? 2 * w - 2 - x : x);
    y = y < 0 ? -y : (y >= h ? 2 * h - 2 - y : y);
    return image.radiance[std::size_t(y) * w + x];
  }
};

float Bilinear(const Mosaic& m, int x, int y, int channel) {
  if (m.At(x, y) == channel) return m.Value(x, y);
  double sum = 0;
  int n = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (m.At(x + dx, y + dy) == channel) {  // the phase repeats: At needs no reflection
        sum += m.Value(x + dx, y + dy);
        ++n;
      }
  return float(sum / n);
}

float Apply(const Mosaic& m, int x, int y, const Kernel& k) {
  double sum = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      if (k[dy + 2][dx + 2] != 0) sum += k[dy + 2][dx + 2] * m.Value(x + dx, y + dy);
  return float(std::max(sum / 8, 0.0));
}

float Malvar(const Mosaic& m, int x, int y, int channel) {
  const int here = m.At(x, y);
  if (here == channel) return m.Value(x, y);
  if (channel == 1) return Apply(m, x, y, kGreenAtRedOrBlue);
  if (here != 1) return Apply(m, x, y, kOppositeAtRedOrBlue);
  return Apply(m, x, y, m.At(x + 1, y) == channel ? kRowChannelAtGreen : kColumnChannelAtGreen);
}

// Any flag within `radius` photosites: the pixels a value was interpolated from.
std::vector<std::uint8_t> SpreadFlags(const HdrImage& image, int radius) {
  const int w = image.width, h = image.height;
  std::vector<std::uint8_t> out(image.flag.size(), kHdrOk);
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t f = kHdrOk;
      for (int dy = std::max(-radius, -y); dy <= std::min(radius, h - 1 - y); ++dy)
        for (int dx = std::max(-radius, -x); dx <= std::min(radius, w - 1 - x); ++dx)
          f |= image.flag[std::size_t(y + dy) * w + x + dx];
      out[std::size_t(y) * w + x] = f;
    }
  return out;
}

}  // namespace

const char* DemosaicMethodName(DemosaicMethod method) {
  return method == DemosaicMethod::kMalvar ? "malvar" : "bilinear";
}

std::optional<DemosaicMethod> ParseDemosaicMethod(const std::string& name) {
  for (DemosaicMethod m : {DemosaicMethod::kBilinear, DemosaicMethod::kMalvar})
    if (name == DemosaicMethodName(m)) return m;
  return std::nullopt;
}

HdrImage Demosaic(HdrImage mosaic, DemosaicMethod method) {
  if (mosaic.cfa == Cfa::kNone) return mosaic;
  if (mosaic.channels != 1 || mosaic.width < 3 || mosaic.height < 3)
    throw std::logic_error("Demosaic: a mosaic is one plane of at least 3 x 3");
  const int w = mosaic.width, h = mosaic.height;
  const std::size_t n = std::size_t(w) * std::size_t(h);
  HdrImage out;
  out.width = w;
  out.height = h;
  out.channels = 3;
  out.radiance.resize(3 * n);
  const Mosaic m{mosaic};
#pragma omp parallel for schedule(static)
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c)
        out.radiance[c * n + std::size_t(y) * w + x] =
            method == DemosaicMethod::kMalvar ? Malvar(m, x, y, c) : Bilinear(m, x, y, c);
  out.flag = SpreadFlags(mosaic, method == DemosaicMethod::kMalvar ? 2 : 1);
  return out;
}

}  // namespace acq
