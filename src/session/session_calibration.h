// A session's calibration from its own board captures (issue 8; docs/architecture.md, "Data flow":
// calibration comes before correspondence). The intrinsics from the held boards of the
// "intrinsics" step, solved with mrcal as `acq calibrate intrinsics` does it (unless the plan
// gives a calibrated lens); then each pose's cam_from_sample from the board lying on the sample
// plane ("board", "board_validation": the same poses as "sample" and "validation"), intrinsics
// locked, the board's symmetric corner orderings resolved with the pose the arms' kinematics
// predict. The board defines the sample frame (calib/extrinsics.h).
//
// Written to calibration/: camera.cameramodel, intrinsics.txt (mrcal's residuals and projection
// uncertainty), corners.vnl (mrcal's corners cache of every board image; images are the HDR
// merges, tone-mapped to 8 bits for the detector), extrinsics.tsv (per pose).
#pragma once

#include <string>
#include <vector>

#include "acq/plan.h"
#include "calib/camera_model.h"
#include "core/gantry_geometry.h"
#include "session/pose_hdr.h"

namespace acq {

struct BoardPoseResult {
  Step step = Step::kBoard;  // kBoard or kBoardValidation
  int pose = 0;
  bool found = false;
  int corners = 0;
  double rms_px = 0;  // per coordinate
  // The calibrated pose against the one the arms' kinematics predict: what calibration fixes.
  double angle_from_kinematics_deg = 0, shift_from_kinematics_mm = 0;
  calib::Pose cam_from_sample;
  ArmAngles arms;          // measured when the board was captured
  bool arms_known = true;  // false: read from an extrinsics.tsv written without them
};

struct SessionCalibration {
  calib::CameraModel camera;
  std::string intrinsics_from;  // "N board captures" or the plan's camera_model file
  int intrinsics_captures = 0, intrinsics_found = 0;
  double intrinsics_rms_px = 0;
  double uncertainty_centre_px = 0, uncertainty_worst_px = 0;  // mrcal's, at the board distance
  std::vector<std::string> warnings;
  std::vector<BoardPoseResult> boards;

  // The calibrated pose at `pose` of `step` (from its board step, BoardStepFor); nullptr when
  // its board was not found.
  const BoardPoseResult* PoseOf(Step step, int pose) const;
};

// The camera and the poses returned are those the files hold (read back after writing them):
// what a later `acq session process` reads, to the last bit. Throws UserError (what to
// recapture) when the intrinsics cannot be solved.
SessionCalibration CalibrateSession(const Plan& plan, const SessionFrames& session,
                                    double* hdr_seconds);

// The calibration CalibrateSession wrote into `session_dir`/calibration (camera.cameramodel,
// extrinsics.tsv; poses to 1e-9 rad and 1e-6 mm, the arms to 1e-9 deg, as written). The
// intrinsics' figures are not in those files and stay zero. UserError naming a file missing or
// malformed.
SessionCalibration ReadSessionCalibration(const std::string& session_dir);

}  // namespace acq
