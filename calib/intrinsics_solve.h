// Intrinsics from chessboard observations, solved with mrcal_optimize() in the stages that
// mrcal-calibrate-cameras uses: a pinhole seed (focal length from OpenCV's closed-form estimate
// unless given, board poses from solvePnP), geometry only, then the pinhole core, then the
// requested lens model with regularization and outlier rejection, then board warp.
#pragma once

#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/board_problem.h"
#include "calib/corners.h"

namespace acq::calib {

struct IntrinsicsOptions {
  std::string lensmodel = "LENSMODEL_OPENCV8";
  double focal_px = 0;  // seed; 0: estimate from the boards
  bool outlier_rejection = true;
  bool board_warp = true;
  int min_boards = 3;  // fewer found boards: refuse
  void Check() const;  // UserError naming the option
};

struct IntrinsicsSolution {
  BoardProblem problem;             // at the optimum
  Selections selections;            // of the final stage (what the uncertainty is computed for)
  std::vector<int> image_of_frame;  // index into the images given, per solved frame
  double rms_per_coordinate = 0;    // mrcal's convention: sqrt(sum of squared x and y / (2N))
  double rms_per_point = 0;         // OpenCV's: sqrt(sum of squared distances / N) = sqrt(2) x
  int inliers = 0;
  double solve_seconds = 0;
};

// Throws UserError when fewer than options.min_boards images have a board.
IntrinsicsSolution SolveIntrinsics(int width, int height, const BoardSpec& board,
                                   const std::vector<BoardObservation>& images,
                                   const IntrinsicsOptions& options);

// Pinhole focal length (px) estimated from the boards' homographies (Zhang's closed form).
double EstimateFocalPx(int width, int height, const BoardSpec& board,
                       const std::vector<BoardObservation>& images);

// The splined model whose field of view covers a pinhole camera of this focal length.
std::string SplinedModelFor(int width, double focal_px, int nx = 16, int ny = 12);

}  // namespace acq::calib
