// What a camera pixel integrates over (issue 19; docs/reconstruction.md, "A camera pixel's
// footprint in the map's renders"): the spread of the points whose light it records, as the
// standard deviation along each axis in pixels. A point-sampling camera (the simulator's default,
// each pixel's centre) has none; a real sensor integrates over its whole pixel (a fill factor of
// one, as microlenses make it), a box of one pixel: 1 / sqrt(12). The simulator's camera with
// `sim.pixel_samples: N` averages N x N points at (i + 1/2) / N of the pixel.
#pragma once

#include <cmath>

namespace acq {

inline constexpr double kWholePixelSpreadPx = 0.28867513459481287;  // 1 / sqrt(12)

// The spread of N x N points evenly spread over a pixel (N = 1: its centre alone, 0).
inline double PixelSamplesSpreadPx(int samples_per_side) {
  if (samples_per_side <= 1) return 0;
  const double n = samples_per_side;
  return std::sqrt((n * n - 1) / 12) / n;
}

}  // namespace acq
