// Synthetic chessboard data with a known camera: board poses spread over the view, exact corner
// projections with seeded noise (mrcal's simulation-first way of testing a calibration), and
// rendered images of the board through any mrcal lens model (blur, noise, quantisation) for the
// detectors and, later, the simulated camera.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/camera_model.h"
#include "calib/corners.h"

namespace acq::calib {

// The camera the tests, the benchmarks and the simulator use when none is given: 1280 x 1024,
// OPENCV8 with a wide-ish lens (f = 1000 px, 65 deg across) whose higher-order and rational
// terms matter at the edges, so the lens-model ladder has something to find.
CameraModel ExampleCamera();

// cam_from_sample for a camera at `camera_in_sample` (mm) looking at the sample centre, its x
// axis horizontal (in the sample's x-y plane) so images are not rolled.
Pose CamFromSampleLookingAtCentre(const Eigen::Vector3d& camera_in_sample);

struct BoardPoseSampling {
  double min_distance_mm = 400, max_distance_mm = 800;  // board centre from the camera
  double max_tilt_deg = 40;         // board normal from the camera's optical axis
  double centre_spread = 0.8;       // board centres within this fraction of the imager
  bool whole_board_in_view = true;  // false: at least half the corners in view
  std::uint64_t seed = 1;
};

// `n` poses cam_from_board whose boards (all corners, with a 1-square margin when
// whole_board_in_view) project inside the imager.
std::vector<Pose> SampleBoardPoses(const CameraModel& camera, const BoardSpec& board, int n,
                                   const BoardPoseSampling& sampling);

// Exact projections of the board's corners plus N(0, noise_px^2) per coordinate, weight 1;
// corners that fall outside the imager are marked missing (weight -1). `warp_mm`: the board
// bowed as mrcal models it (BoardSpec::CornersInBoard).
std::vector<BoardObservation> SynthesizeCorners(
    const CameraModel& camera, const BoardSpec& board, const std::vector<Pose>& cam_from_board,
    double noise_px, std::uint64_t seed, const Eigen::Vector2d& warp_mm = Eigen::Vector2d::Zero());

struct BoardRenderOptions {
  int supersample = 4;                               // per axis, for anti-aliased edges
  double blur_px = 0.6;                              // Gaussian sigma of the optics
  double black = 30, white = 220, background = 128;  // 8-bit grey levels
  double noise_dn = 1.0;                             // Gaussian read noise, grey levels
  double ray_grid_step_px = 4;  // rays unprojected on this grid and interpolated between
  std::uint64_t seed = 1;
};

// The board (with a white margin one square wide) seen by `camera` from cam_from_board, as an
// 8-bit grey image of the camera's size.
cv::Mat RenderBoard(const CameraModel& camera, const BoardSpec& board, const Pose& cam_from_board,
                    const BoardRenderOptions& options);

}  // namespace acq::calib
