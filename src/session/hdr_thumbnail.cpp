#include "session/hdr_thumbnail.h"

#include <algorithm>
#include <filesystem>

#include "acq/map_render.h"

namespace acq {
namespace {

// At most this many pixels a side of a block are read (evenly spaced): the thumbnail of a
// 2048-pixel frame then reads 1/7 of it, on a worker that shares the cores with the capture.
constexpr int kReadPerSide = 4;

// The block means (3 channels, a mono image repeated) and whether a block holds a saturated
// pixel, from up to kReadPerSide^2 pixels of each; `scale` source pixels a side per block.
RgbImage BoxAverage(const HdrImage& hdr, int scale, std::vector<bool>* saturated) {
  const int stride = std::max(1, scale / kReadPerSide);
  RgbImage out{std::max(1, hdr.width / scale), std::max(1, hdr.height / scale), {}};
  out.rgb.assign(std::size_t(out.width) * out.height * 3, 0.0f);
  saturated->assign(std::size_t(out.width) * out.height, false);
  for (int ty = 0; ty < out.height; ++ty)
    for (int tx = 0; tx < out.width; ++tx) {
      const std::size_t t = std::size_t(ty) * out.width + tx;
      int n = 0;
      for (int y = ty * scale; y < std::min(hdr.height, (ty + 1) * scale); y += stride)
        for (int x = tx * scale; x < std::min(hdr.width, (tx + 1) * scale); x += stride, ++n) {
          const std::size_t p = std::size_t(y) * hdr.width + x;
          for (int c = 0; c < 3; ++c)
            out.rgb[3 * t + c] += hdr.Plane(std::min(c, hdr.channels - 1))[p];
          if (!hdr.flag.empty() && hdr.flag[p] == kHdrSaturated) (*saturated)[t] = true;
        }
      for (int c = 0; c < 3; ++c) out.rgb[3 * t + c] /= float(std::max(1, n));
    }
  return out;
}

}  // namespace

void WriteHdrThumbnail(const HdrImage& hdr, const std::string& path) {
  const int scale =
      std::max(1, (std::max(hdr.width, hdr.height) + kThumbnailMaxSide - 1) / kThumbnailMaxSide);
  std::vector<bool> saturated;
  RgbImage image = BoxAverage(hdr, scale, &saturated);
  std::vector<float> unflagged;
  for (std::size_t t = 0; t < saturated.size(); ++t)
    if (!saturated[t]) unflagged.insert(unflagged.end(), &image.rgb[3 * t], &image.rgb[3 * t] + 3);
  const double exposure = AutoExposure(std::move(unflagged));
  for (std::size_t t = 0; t < saturated.size(); ++t)
    if (saturated[t]) {
      image.rgb[3 * t] = image.rgb[3 * t + 2] = float(1.0 / exposure);
      image.rgb[3 * t + 1] = 0.0f;
    }
  // Written aside and renamed, as every file of a session: a kill leaves the old one or none.
  const std::string aside = path + ".partial.png";
  WritePng(image, aside, exposure);
  std::filesystem::rename(aside, path);
}

}  // namespace acq
