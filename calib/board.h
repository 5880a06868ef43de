// A planar chessboard target: its inner-corner grid and spacing, and the board frame in which
// mrcal places its corners (corner (i, j) at (i * spacing, j * spacing, 0), i along the width).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace acq::calib {

struct BoardSpec {
  int width_n = 10;   // inner corners along the board's x axis
  int height_n = 10;  // inner corners along y
  double spacing_mm = 20;

  int Corners() const { return width_n * height_n; }
  // Throws UserError (where = `where`) unless both counts are >= 2 and the spacing is positive.
  void Check(const std::string& where) const;
  // Corner positions in the board frame, row-major (j outer, i inner), as mrcal orders them.
  // `warp_mm` is mrcal's board warp (x2, y2): the board bowed out of its plane along two
  // parabolas, z = x2 * 4u(1-u) + y2 * 4v(1-v) with u, v from 0 to 1 across the corner grid.
  std::vector<Eigen::Vector3d> CornersInBoard(
      const Eigen::Vector2d& warp_mm = Eigen::Vector2d::Zero()) const;
  Eigen::Vector3d Centre() const;  // of the corner grid, in the board frame
};

// "WxH" (inner corners, e.g. "10x10" or "9x6") -> width_n, height_n. UserError naming `where`.
BoardSpec ParseBoardSize(const std::string& text, double spacing_mm, const std::string& where);

}  // namespace acq::calib
