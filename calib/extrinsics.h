// Extrinsics at a gantry pose: cam_from_sample from one image of the board lying in the sample
// plane, intrinsics locked. The sample frame (docs/architecture.md, "Conventions") is defined by
// the board: origin at the centre of its corner grid, x along the board's x (lay the board with x
// towards gantry azimuth 0), z the surface normal towards the arms. mrcal's board frame has z
// pointing into the board (away from a camera that sees its face), so sample_from_board is a half
// turn about x and a shift to the centre.
#pragma once

#include <optional>

#include "calib/board.h"
#include "calib/camera_model.h"
#include "calib/corners.h"

namespace acq::calib {

Pose SampleFromBoard(const BoardSpec& board);

struct ExtrinsicsResult {
  Pose cam_from_sample;
  double rms_px = 0;                   // per coordinate, inliers
  int corners = 0;                     // used
  int symmetry = 0;                    // which re-ordering of the detected corners was taken
  double angle_from_expected_deg = 0;  // 0 when no expected pose was given
};

// A detector may return a symmetric board's corners in any of its orderings (rotations); with
// `expected` (the pose the gantry's kinematics predict) the ordering closest to it is taken, so
// the sample frame follows the board's printed axes rather than the detector's choice. Without
// it the detector's order is used. UserError when the board has fewer than 4 corners.
ExtrinsicsResult SolveCamFromSample(const CameraModel& camera, const BoardSpec& board,
                                    const BoardObservation& observation,
                                    const std::optional<Pose>& expected = std::nullopt);

}  // namespace acq::calib
