#include "calib/board.h"

#include <cstdio>

#include "core/error.h"

namespace acq::calib {

void BoardSpec::Check(const std::string& where) const {
  if (width_n < 2 || height_n < 2)
    throw UserError(where,
                    "a board needs at least 2 x 2 inner corners, got " + std::to_string(width_n) +
                        "x" + std::to_string(height_n),
                    "count the inner corners (where four squares meet), e.g. --board 9x6");
  if (!(spacing_mm > 0))
    throw UserError(where, "the corner spacing must be positive",
                    "give --spacing-mm, the side of one square in millimetres");
}

std::vector<Eigen::Vector3d> BoardSpec::CornersInBoard(const Eigen::Vector2d& warp_mm) const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(Corners());
  for (int j = 0; j < height_n; ++j)
    for (int i = 0; i < width_n; ++i) {
      const double u = static_cast<double>(i) / (width_n - 1);
      const double v = static_cast<double>(j) / (height_n - 1);
      const double z = warp_mm.x() * 4 * u * (1 - u) + warp_mm.y() * 4 * v * (1 - v);
      out.emplace_back(i * spacing_mm, j * spacing_mm, z);
    }
  return out;
}

Eigen::Vector3d BoardSpec::Centre() const {
  return {0.5 * (width_n - 1) * spacing_mm, 0.5 * (height_n - 1) * spacing_mm, 0.0};
}

BoardSpec ParseBoardSize(const std::string& text, double spacing_mm, const std::string& where) {
  BoardSpec board;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &board.width_n, &board.height_n, &tail) != 2)
    throw UserError(where, "expected the board as WxH inner corners, got '" + text + "'",
                    "e.g. --board 10x10 or --board 9x6");
  board.spacing_mm = spacing_mm;
  board.Check(where);
  return board;
}

}  // namespace acq::calib
