#include "session/frame_preview.h"

#include <algorithm>
#include <cmath>

namespace acq {
namespace {

// The mean of the 2 x 2 block at (x0, y0) as a share of the sensor's maximum, and whether one
// of its pixels is at that maximum.
struct Block {
  double value;
  bool clipped;
};
Block BlockAt(const Frame& frame, int x0, int y0) {
  const std::uint16_t* row0 = &frame.pixels[std::size_t(y0) * frame.width + x0];
  const std::uint16_t* row1 = row0 + frame.width;
  const int top = std::max({row0[0], row0[1], row1[0], row1[1]});
  const double max = std::max(frame.MaxValue(), 1);
  return {std::min((row0[0] + row0[1] + row1[0] + row1[1]) / (4 * max), 1.0),
          top >= frame.MaxValue()};
}

std::uint8_t DisplayGrey(double value) {
  return std::uint8_t(std::lround(255 * std::pow(value, 1 / 2.2)));
}

void SampleWholeFrame(const Frame& frame, int max_side, FramePreview& p) {
  int stride = (std::max(frame.width, frame.height) + max_side - 1) / max_side;
  stride = std::max(2, stride + (stride % 2));  // even: whole 2 x 2 colour quads
  p.width = (frame.width - 1) / stride + 1;
  p.height = (frame.height - 1) / stride + 1;
  p.grey.resize(std::size_t(p.width) * p.height);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      const Block b = BlockAt(frame, std::min(x * stride, frame.width - 2),
                              std::min(y * stride, frame.height - 2));
      p.grey[std::size_t(y) * p.width + x] = DisplayGrey(b.value);
      ++p.histogram[std::min(int(b.value * p.histogram.size()), int(p.histogram.size()) - 1)];
      ++p.sampled;
      p.clipped += b.clipped;
    }
}

// The centre's blocks at full block resolution and their sharpness (frame_preview.h).
void FocusOnCentre(const Frame& frame, FramePreview& p) {
  p.focus_width = std::min(kFocusSide, frame.width / 2);
  p.focus_height = std::min(kFocusSide, frame.height / 2);
  // Even origins: a Bayer quad is never split.
  const int x0 = (frame.width / 2 - p.focus_width) & ~1,
            y0 = (frame.height / 2 - p.focus_height) & ~1;
  std::vector<double> v(std::size_t(p.focus_width) * p.focus_height);
  for (int y = 0; y < p.focus_height; ++y)
    for (int x = 0; x < p.focus_width; ++x)
      v[std::size_t(y) * p.focus_width + x] = BlockAt(frame, x0 + 2 * x, y0 + 2 * y).value;
  p.focus_grey.resize(v.size());
  std::transform(v.begin(), v.end(), p.focus_grey.begin(), DisplayGrey);
  double sum = 0, energy = 0;
  long pairs = 0;
  for (int y = 0; y < p.focus_height; ++y)
    for (int x = 0; x < p.focus_width; ++x) {
      const double here = v[std::size_t(y) * p.focus_width + x];
      sum += here;
      if (x + 1 < p.focus_width) {
        energy += std::pow(v[std::size_t(y) * p.focus_width + x + 1] - here, 2);
        ++pairs;
      }
      if (y + 1 < p.focus_height) {
        energy += std::pow(v[std::size_t(y + 1) * p.focus_width + x] - here, 2);
        ++pairs;
      }
    }
  const double mean = sum / double(v.size());
  p.sharpness = pairs > 0 && mean > 0 ? energy / double(pairs) / (mean * mean) : 0;
}

}  // namespace

FramePreview PreviewOf(const Frame& frame, int max_side) {
  FramePreview p;
  p.source_width = frame.width;
  p.source_height = frame.height;
  p.exposure_us = frame.exposure_us;
  if (frame.width < 2 || frame.height < 2 ||
      frame.pixels.size() < std::size_t(frame.width) * frame.height)
    return p;
  SampleWholeFrame(frame, max_side, p);
  FocusOnCentre(frame, p);
  return p;
}

}  // namespace acq
