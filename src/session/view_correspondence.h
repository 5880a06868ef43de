// Where each reference pixel lands in a view (issue 8; calib/correspondence.h), for a session:
// the reference view the maps are on, and each pose's correspondence map from its board pose
// (where the pixels land) and its arms (where the light and the camera are), written to
// correspondence/<step>_NNN.exr. A map is computed once (issue 21): the file records its inputs,
// and a file whose inputs are those of the calibration at hand is read back instead, so the
// maps computed while the capture went on (background.h) and by an earlier `acq session
// process` are not computed again.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "acq/plan.h"
#include "calib/correspondence.h"
#include "core/gantry_geometry.h"
#include "core/session_vocabulary.h"
#include "io/float_planes_exr.h"
#include "session/session_calibration.h"

namespace acq {

// The calibrated camera straight above the sample centre (in the frame the board defined),
// cropped to the sample, centred on the sample's centre as that camera sees it.
calib::ReferenceView ReferenceViewOf(const Plan& plan, const calib::CameraModel& camera);

// The view of a pose: the camera and its board pose, the light and the camera's eye from the
// arms measured at the pose.
calib::CalibratedView CalibratedViewOf(const Plan& plan, const calib::CameraModel& camera,
                                       const BoardPoseResult& board, const ArmAngles& arms);

// The reference view with its pixels' points on the sample (calib::SamplePoints), computed on
// first use and kept: they are the same for every view's map. One thread's.
class SessionReference {
 public:
  explicit SessionReference(calib::ReferenceView view) : view_(std::move(view)) {}
  const calib::ReferenceView& view() const { return view_; }
  const std::vector<Eigen::Vector3d>& points();

 private:
  calib::ReferenceView view_;
  std::optional<std::vector<Eigen::Vector3d>> points_;
};

// The pose's correspondence map, computed and written or read back when up to date; adds the
// time taken to `*seconds`.
FloatPlanes PoseCorrespondence(const std::string& session_dir, Step step, int pose,
                               SessionReference& reference, const calib::CalibratedView& view,
                               double* seconds);

}  // namespace acq
