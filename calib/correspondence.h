// Correspondence maps (docs/architecture.md, "Alignment"): every reference-view pixel is a point on
// the sample plane (its ray from the reference camera meets z = 0 of the sample frame); that point
// is projected into each view with the view's calibrated camera and cam_from_sample, and gets
// its own light and view directions from where the light and the camera actually are (both
// may be near). One map per view, written as float planes (docs/calibration.md):
//   x, y            sub-pixel position in the view (mrcal's pixel convention), NaN if not visible
//   visible         1 where the point is in the view's imager and faces its camera, else 0
//   sample.x/y      the point on the sample plane, mm (same in every view's map)
//   wi.x/y/z        unit direction to the light, sample frame
//   wo.x/y/z        unit direction to the camera, sample frame
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/camera_model.h"
#include "io/float_planes_exr.h"

namespace acq::calib {

struct CalibratedView {
  CameraModel camera;  // intrinsics (usually shared by all views)
  Pose cam_from_sample;
  Eigen::Vector3d light_in_sample_mm = Eigen::Vector3d(0, 0, 1000);  // the point light
  // Where the view directions (wo) point from, when known better than cam_from_sample's centre.
  // A long lens sees a flat board almost orthographically: its image pins down where the
  // sample lands in the view, but trades the camera's sideways position against its rotation,
  // so the centre it gives can be off by a degree as seen from the sample (docs/calibration.md).
  std::optional<Eigen::Vector3d> eye_in_sample_mm;
};

struct ReferenceView {
  CameraModel camera;
  Pose cam_from_sample;  // the camera at theta = 0
  // Rows/columns of the reference image the maps cover (default: all).
  int x0 = 0, y0 = 0, width = 0, height = 0;
};

// The map of one view. `reference` decides the pixels; `view` where they land.
FloatPlanes ComputeCorrespondence(const ReferenceView& reference, const CalibratedView& view);
// The same with the reference's SamplePoints given: they are the same for every view of a
// session, and cost 2 s of mrcal's unprojection at 2048 x 2048.
FloatPlanes ComputeCorrespondence(const ReferenceView& reference,
                                  const std::vector<Eigen::Vector3d>& sample_points,
                                  const CalibratedView& view);

// Points on the sample plane seen by the reference pixels (mm, sample frame); NaN where the ray
// misses the plane.
std::vector<Eigen::Vector3d> SamplePoints(const ReferenceView& reference);

// The light (or camera) at gantry arm angles theta (zenith), phi (azimuth, 0 along sample x) and
// distance from the sample centre, in the sample frame.
Eigen::Vector3d ArmPositionInSample(double theta, double phi, double distance_mm);

}  // namespace acq::calib
