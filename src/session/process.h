// acqd's processing of a session's captures (issue 8): each pose's bracket merged into an HDR
// image (hdr/<step>_NNN.exr), the reference view's pixels found in each pose's view
// (correspondence/<step>_NNN.exr), the per-pixel reconstruction into svbrdf.exr, and the
// validation views compared with the map's renders (renders/), all in the session directory.
//
// Calibration first (session_calibration.h): the intrinsics and each pose's cam_from_sample
// from the session's own board captures; a view whose board was not found is left out (and
// said so), never aligned from the arms' kinematics. Where each pixel lands in a view comes from
// its board pose; the view directions (wo) from the camera's arm, like the light's: a long lens
// sees the flat board almost orthographically and the board's pose trades the camera's
// sideways position against its rotation (measured on the simulated instrument: the centre the
// board gives is 0.2 to 1.2 deg off as seen from the sample, the most for the views nearest the
// normal, while its projection is within 0.3 px; the map's error 0.465 with the board's centres,
// 0.436 with the arm's).
//
// Radiometry: with the plan's Spectralon captures, each view's light is measured on the
// Spectralon at the same pose (correspondence_source.h); without them, the point-light model
// with SessionGeometry::light_intensity. The light's position comes from its arm's angles.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "acq/colour_chart_fit.h"
#include "acq/plan.h"
#include "acq/reconstruction_job.h"
#include "acq/validation.h"
#include "calib/camera_model.h"
#include "io/float_planes_exr.h"
#include "io/session_catalog.h"
#include "session/session_calibration.h"

namespace acq {

struct SessionGeometry {
  double light_intensity = 0;  // in HDR units (counts per us at 0 dB) x mm^2; without Spectralon
};
// The catalog's decision that records SessionGeometry::light_intensity where the session has
// no Spectralon captures (acqd knows it from the simulated world), for `acq process`.
inline constexpr const char* kLightIntensityDecision = "light_intensity";

struct ValidationSummary {
  std::string name;  // the validation direction
  long pixels = 0;
  double relative_rms = 0, median_relative = 0;
  double median_delta_e2000 = 0;   // ValidationResult's
  std::string render;              // PNG: the map's render beside the capture
  int worst_x = -1, worst_y = -1;  // ValidationResult's worst pixel and its share
  double worst_share = 0;
};

struct ProcessReport {
  double hdr_s = 0, calibration_s = 0, correspondence_s = 0, reconstruction_s = 0, validation_s = 0;
  SessionCalibration calibration;
  std::vector<std::string> views_left_out;  // poses whose board was not found
  int reference_width = 0, reference_height = 0;
  double pixel_size_mm = 0;
  ReconstructionReport reconstruction;
  std::vector<ValidationSummary> validation;
  // A colour camera's matrix as the processing used it (the plan's, or fitted from the chart).
  std::optional<Eigen::Matrix3d> rec709_from_camera;
  std::optional<ChartFit> chart;  // camera.colour_chart: the fit and each patch's residual
};

// What was computed before the processing runs, taken as it is instead of computed again or
// read back from disk: by the worker during the capture (background.h) or, for a reprocess from
// the reconstruction, the calibration read back.
struct PrecomputedStages {
  std::optional<SessionCalibration> calibration;  // from this session's board captures
  std::map<std::pair<Step, int>, PoseHdr> poses;  // merged poses (not the boards')
  // Per view, for `calibration` (a map made for another calibration is never here).
  std::map<std::pair<Step, int>, FloatPlanes> correspondence;
};

// Computes what `precomputed` lacks.
ProcessReport ProcessSession(const Plan& plan, SessionCatalog& catalog,
                             const SessionGeometry& geometry, PrecomputedStages precomputed = {});

}  // namespace acq
