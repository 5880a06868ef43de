// Detected chessboard corners per image, and the corners cache: the vnlog file mrcal's own tools
// read and write (`mrcal-calibrate-cameras --corners-cache`). One row per corner,
// "filename x y level", in mrcal's order (row-major over the board); weight = 2^-level; a
// corner not seen is "- - -"; an image with no board is one row "filename - - -".
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/board.h"

namespace acq::calib {

struct BoardObservation {
  std::string image;  // as named in the cache (relative to the cache's folder or absolute)
  // x, y (pixels, mrcal's convention: the centre of the top-left pixel is (0, 0)) and weight;
  // weight < 0: corner not detected or rejected. Empty: no board found in this image.
  std::vector<Eigen::Vector3d> corners;

  bool found() const { return !corners.empty(); }
  int DetectedCorners() const;
};

void WriteCornersCache(const std::string& path, const std::vector<BoardObservation>& images);
// UserError naming file:line on malformed rows or a corner count that is not the board's.
std::vector<BoardObservation> ReadCornersCache(const std::string& path, const BoardSpec& board);

// Which cells of an nx x ny grid over a width x height imager hold a detected corner (row-major).
std::vector<bool> CoveredCells(int width, int height, const std::vector<BoardObservation>& images,
                               int nx, int ny);

// The board's symmetric re-orderings (4 rotations of a square grid, 2 otherwise): a detector may
// return any of them. Each entry maps output index -> input index.
std::vector<std::vector<int>> BoardSymmetries(const BoardSpec& board);

}  // namespace acq::calib
