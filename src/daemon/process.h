// acqd's processing of a session's captures (issue 8): each pose's bracket merged into an HDR
// image (hdr/<step>_NNN.exr), the reference view's pixels found in each pose's view
// (correspondence/<step>_NNN.exr), the per-pixel reconstruction into svbrdf.exr, and the
// validation views compared with the map's renders (renders/), all in the session directory.
//
// Radiometry: with the plan's Spectralon captures, each view's light is measured on the
// Spectralon at the same pose (correspondence_source.h); without them, the point-light model
// with SessionGeometry::light_intensity.
//
// DEPARTURE, until the board stage is built into acqd: the camera's pose in each view comes from
// the gantry's kinematics (the measured arm angles recorded with every frame, the camera looking
// at the sample centre) instead of from a board capture at that pose, and the intrinsics are
// given (SessionGeometry::camera). On the simulated instrument both are exact; on a real one
// they are not good enough (millimetres of arm error are pixels of misalignment), which is why
// calibration/ exists.
#pragma once

#include <string>
#include <vector>

#include "acq/plan.h"
#include "acq/reconstruction_job.h"
#include "acq/validation.h"
#include "calib/camera_model.h"
#include "io/session_catalog.h"

namespace acq {

struct SessionGeometry {
  calib::CameraModel camera;   // the intrinsics (every view, and the reference view)
  double light_intensity = 0;  // in HDR units (counts per us at 0 dB) x mm^2; without Spectralon
};

struct ValidationSummary {
  std::string name;  // the validation direction
  long pixels = 0;
  double relative_rms = 0, median_relative = 0;
  std::string render;  // PNG: the map's render beside the capture
};

struct ProcessReport {
  double hdr_s = 0, correspondence_s = 0, reconstruction_s = 0, validation_s = 0;
  int reference_width = 0, reference_height = 0;
  double pixel_size_mm = 0;
  std::vector<Eigen::Vector3d> sample_points;  // of the reference pixels (mm, sample frame)
  ReconstructionReport reconstruction;
  std::vector<ValidationSummary> validation;
};

ProcessReport ProcessSession(const Plan& plan, SessionCatalog& catalog,
                             const SessionGeometry& geometry);

}  // namespace acq
