// acqd's processing of the sample's captures (issue 8): each pose's bracket merged into an HDR
// image (hdr/NNN.exr), the reference view's pixels found in each pose's view (correspondence/
// NNN.exr), and the per-pixel reconstruction into svbrdf.exr, all in the session directory.
//
// DEPARTURE, until the calibration stage is built into acqd: the camera's pose in each view
// comes from the gantry's kinematics (the measured arm angles recorded with every frame, the
// camera looking at the sample centre) instead of from a board capture at that pose, and the
// light's intensity in the camera's units is given instead of measured on a Spectralon. On the
// simulated instrument both are exact; on a real one they are not good enough (millimetres of
// arm error are pixels of misalignment), which is why calibration/ exists.
#pragma once

#include <string>

#include "acq/move_planner.h"
#include "acq/plan.h"
#include "acq/reconstruction_job.h"
#include "calib/camera_model.h"
#include "io/session_catalog.h"

namespace acq {

struct SessionGeometry {
  calib::CameraModel camera;   // the intrinsics (every view, and the reference view)
  double light_intensity = 0;  // in HDR units (counts per us at 0 dB) x mm^2
};

struct ProcessReport {
  double hdr_s = 0, correspondence_s = 0, reconstruction_s = 0;
  int reference_width = 0, reference_height = 0;
  double pixel_size_mm = 0;
  ReconstructionReport reconstruction;
};

ProcessReport ProcessSample(const Plan& plan, SessionCatalog& catalog,
                            const SessionGeometry& geometry);

}  // namespace acq
