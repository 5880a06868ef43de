// The one rule that lays a grid of pixels on the sample plane: maps, synthetic layouts and the
// simulator's cards all use it. The grid is centred on the sample frame's origin and seen as the
// reference camera sees it (straight down, its image x along the sample's x): its columns run to
// the sample's +x and its rows to the sample's -y, so a grid drawn row 0 on top is the sample
// as seen from above (docs/architecture.md, "Conventions").
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

namespace acq {

struct SampleGrid {
  int width = 0, height = 0;  // columns, rows
  double width_mm = 0, height_mm = 0;

  // The sample-plane point (mm) at the centre of pixel (x, y).
  Eigen::Vector2d CentreOf(int x, int y) const {
    return {((x + 0.5) / width - 0.5) * width_mm, (0.5 - (y + 0.5) / height) * height_mm};
  }

  // The pixel a sample-plane point falls in, row-major; -1 off the grid.
  long PixelAt(const Eigen::Vector2d& p) const {
    if (!(width_mm > 0 && height_mm > 0) || !p.allFinite()) return -1;
    const double x = std::floor((p.x() / width_mm + 0.5) * width);
    const double y = std::floor((0.5 - p.y() / height_mm) * height);
    if (x < 0 || y < 0 || x >= width || y >= height) return -1;
    return long(y) * width + long(x);
  }

  // The slope of a height field (per unit along the sample's x and y) from its differences along
  // the columns and down the rows: down the rows is the sample's -y.
  static Eigen::Vector2d SlopeOf(double along_columns, double down_rows) {
    return {along_columns, -down_rows};
  }
};

// Turns a row-major plane of `width` columns upside down: how a grid stored before this rule
// (rows to the sample's +y: synthetic maps and simulated cards before 2026-12-03) is read.
template <class T>
void FlipGridRows(std::vector<T>* plane, int width) {
  const std::size_t w = std::size_t(width), rows = w ? plane->size() / w : 0;
  for (std::size_t r = 0; r < rows / 2; ++r)
    std::swap_ranges(plane->begin() + long(r * w), plane->begin() + long((r + 1) * w),
                     plane->begin() + long((rows - 1 - r) * w));
}

}  // namespace acq
