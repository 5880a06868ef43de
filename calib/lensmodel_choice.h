// "Model no more than the scene needs" (docs/lens-model-choice.md): fit a ladder of lens models,
// cross-validate each by solving the two halves of the images separately and comparing the
// halves' projections, and pick the simplest model whose cross-validation difference is within
// the noise: the smallest difference on the ladder (see the document for why not the richest's).
#pragma once

#include <string>
#include <vector>

#include "calib/intrinsics_solve.h"

namespace acq::calib {

struct LadderRow {
  std::string lensmodel;
  int params = 0;
  double rms_per_coordinate = 0;  // full data set
  double cv_diff_px = 0;          // RMS over the imager region both halves observed, A vs B
  int cv_points = 0;              // grid points compared
  int cv_diverged = 0;            // of those, points where a half's model does not project
  double solve_seconds = 0;       // full data set solve
};

struct LensModelChoice {
  std::vector<LadderRow> rows;
  int chosen = -1;
  double noise_ratio = 1.5;   // accepted: cv_diff <= noise_ratio x noise_floor_px
  double noise_floor_px = 0;  // the smallest cv_diff on the ladder among models that project
};

// OPENCV4, OPENCV5, OPENCV8 and a 16 x 12 cubic spline covering the view.
std::vector<std::string> DefaultLadder(int width, double focal_px);

// The centres of the cells of a 32 x 24 grid over the imager that hold corners in both `a` and
// `b`: where two solves from those images are both constrained by data. Compared elsewhere, a
// spline fitted to one half is extrapolated by its regularization alone and may not project at
// all (the `inf` the ladder once printed, docs/lens-model-choice.md).
std::vector<Eigen::Vector2d> SharedObservedPixels(int width, int height,
                                                  const std::vector<BoardObservation>& a,
                                                  const std::vector<BoardObservation>& b);

struct ProjectionDiff {
  double rms_px = 0;  // over the points both models project
  int points = 0;     // points compared
  int diverged = 0;   // points where a model gives no finite unprojection or projection
};

// Projection difference between two solves of one camera: `pixels` are unprojected by `a` to
// points at `distance_mm`, moved by the best-fit rigid transform between the two models' points
// (each solve's camera frame is only defined through its boards, so the two differ by a small
// motion) and projected by `b`. RMS, pixels.
ProjectionDiff ProjectionDifference(const CameraModel& a, const CameraModel& b,
                                    const std::vector<Eigen::Vector2d>& pixels, double distance_mm);

LensModelChoice ChooseLensModel(int width, int height, const BoardSpec& board,
                                const std::vector<BoardObservation>& images,
                                const IntrinsicsOptions& options,
                                const std::vector<std::string>& ladder);

void PrintLadder(std::FILE* out, const LensModelChoice& choice);

}  // namespace acq::calib
