// Relief on a simulated sample (issue 19): a height map from which the renderer takes each
// point's true normal. The built-in relief embosses what is printed (every pixel whose label is
// not the background's, 0) and raises a border around the sample, both with sloped edges whose
// steepest slope is `slope_deg`, and adds a fine paper-fibre noise of RMS slope `fibre_deg`. A
// height map may also come from a file (EXR plane "height", in pixels of the sample's grid; or a
// grey PNG scaled by `png_height_px`). Heights are in units of a pixel's width, so slopes are
// the height map's gradient.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/synthetic_svbrdf.h"

namespace acq::sim {

struct ReliefOptions {
  double slope_deg = 10;       // the steepest slope of the embossed edges and border
  double fibre_deg = 0;        // RMS slope of the fibre noise (0: none)
  double edge_px = 1.5;        // the embossing's edge width (Gaussian sigma, pixels)
  double border_share = 0.05;  // the raised border's width, as a share of the sample's side
  std::uint64_t seed = 1;
  void Check() const;  // throws UserError
};

// The built-in relief's height map for `layout` (width * height, row-major).
std::vector<float> CardRelief(const SyntheticSvbrdf& layout, const ReliefOptions& options);

// A height map PNG's full scale, in pixels of the map: 8 (a 16-bit PNG's step is 1/8192 pixel).
inline constexpr double kPngHeightFullScalePx = 8.0;

// A height map read from a file, which must be the layout's size (UserError naming both sizes).
std::vector<float> ReadHeightMap(const std::string& path, int width, int height,
                                 double png_height_px);

// Sets layout->normal from a height map (central differences, one-sided at the edges).
void SetNormalsFromHeight(SyntheticSvbrdf* layout, const std::vector<float>& height);

}  // namespace acq::sim
