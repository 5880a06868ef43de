#include "session/frame_preview.h"

#include <algorithm>
#include <cmath>

namespace acq {

FramePreview PreviewOf(const Frame& frame, int max_side) {
  FramePreview p;
  p.source_width = frame.width;
  p.source_height = frame.height;
  p.exposure_us = frame.exposure_us;
  if (frame.width < 2 || frame.height < 2 ||
      frame.pixels.size() < std::size_t(frame.width) * frame.height)
    return p;
  int stride = (std::max(frame.width, frame.height) + max_side - 1) / max_side;
  stride = std::max(2, stride + (stride % 2));  // even: whole 2 x 2 colour quads
  p.width = (frame.width - 1) / stride + 1;
  p.height = (frame.height - 1) / stride + 1;
  p.grey.resize(std::size_t(p.width) * p.height);
  const double max = std::max(frame.MaxValue(), 1);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const int x0 = std::min(x * stride, frame.width - 2),
                y0 = std::min(y * stride, frame.height - 2);
      const std::uint16_t* row0 = &frame.pixels[std::size_t(y0) * frame.width + x0];
      const std::uint16_t* row1 = row0 + frame.width;
      const int top = std::max({row0[0], row0[1], row1[0], row1[1]});
      const double v = std::min((row0[0] + row0[1] + row1[0] + row1[1]) / (4 * max), 1.0);
      p.grey[std::size_t(y) * p.width + x] = std::uint8_t(std::lround(255 * std::pow(v, 1 / 2.2)));
      ++p.histogram[std::min(int(v * p.histogram.size()), int(p.histogram.size()) - 1)];
      ++p.sampled;
      p.clipped += top >= frame.MaxValue();
    }
  return p;
}

}  // namespace acq
