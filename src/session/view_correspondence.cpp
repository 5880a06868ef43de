#include "session/view_correspondence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "calib/synthetic_board.h"
#include "core/seconds_since.h"
#include "session/pose_hdr.h"

namespace acq {
namespace {

// Everything a correspondence map is computed from, to the last bit: the attribute that says
// whether a map on disk is the one these inputs give.
std::string InputsText(const calib::ReferenceView& r, const calib::CalibratedView& v) {
  std::ostringstream s;
  s.precision(17);
  auto camera = [&s](const calib::CameraModel& c) {
    s << c.lensmodel_name() << " " << c.width() << "x" << c.height();
    for (double x : c.intrinsics()) s << " " << x;
  };
  auto pose = [&s](const calib::Pose& p) {
    s << " r " << p.r.transpose() << " t " << p.t.transpose();
  };
  s << "reference ";
  camera(r.camera);
  pose(r.cam_from_sample);
  s << " crop " << r.x0 << " " << r.y0 << " " << r.width << " " << r.height << "; view ";
  camera(v.camera);
  pose(v.cam_from_sample);
  s << " light " << v.light_in_sample_mm.transpose();
  if (v.eye_in_sample_mm) s << " eye " << v.eye_in_sample_mm->transpose();
  return s.str();
}

constexpr const char* kInputsAttribute = "acqInputs";

}  // namespace

calib::ReferenceView ReferenceViewOf(const Plan& plan, const calib::CameraModel& camera) {
  calib::ReferenceView reference;
  reference.camera = camera;
  const double distance = plan.gantry.camera_distance_mm;
  reference.cam_from_sample = calib::CamFromSampleLookingAtCentre({0, 0, distance});
  const double pixel_size_mm = distance / camera.intrinsics()[0];
  const int w = camera.width(), h = camera.height();
  reference.width = std::min(w, int(plan.sample.width_mm / pixel_size_mm));
  reference.height = std::min(h, int(plan.sample.height_mm / pixel_size_mm));
  // Centred on the sample's centre as the calibrated camera sees it: its principal point is
  // not the image centre, and pixels off the sample would be reconstructions of the cloth.
  const Eigen::Vector2d centre =
      camera.Project(reference.cam_from_sample * Eigen::Vector3d::Zero());
  reference.x0 = std::clamp(int(std::lround(centre.x() - reference.width / 2.0 + 0.5)), 0,
                            w - reference.width);
  reference.y0 = std::clamp(int(std::lround(centre.y() - reference.height / 2.0 + 0.5)), 0,
                            h - reference.height);
  return reference;
}

calib::CalibratedView CalibratedViewOf(const Plan& plan, const calib::CameraModel& camera,
                                       const BoardPoseResult& board, const ArmAngles& arms) {
  // Where pixels land: the board's pose; where the camera is: its arm (the view directions).
  return {
      camera, board.cam_from_sample,
      calib::ArmPositionInSample(arms.light_theta, arms.light_phi, plan.gantry.light_distance_mm),
      calib::ArmPositionInSample(arms.camera_theta, arms.camera_phi,
                                 plan.gantry.camera_distance_mm)};
}

const std::vector<Eigen::Vector3d>& SessionReference::points() {
  if (!points_) points_ = calib::SamplePoints(view_);
  return *points_;
}

FloatPlanes PoseCorrespondence(const std::string& session_dir, Step step, int pose,
                               SessionReference& reference, const calib::CalibratedView& view,
                               double* seconds) {
  const auto start = SteadyClock::now();
  const std::string path = session_dir + "/correspondence/" + PoseName(step, pose) + ".exr";
  const std::string inputs = InputsText(reference.view(), view);
  if (std::filesystem::is_regular_file(path)) {
    try {
      FloatPlanes known = ReadFloatPlanesExr(path);
      const auto a = known.attributes.find(kInputsAttribute);
      if (a != known.attributes.end() && a->second == inputs) {
        *seconds += SecondsSince(start);
        return known;
      }
    } catch (const std::exception&) {  // unreadable (a crash while writing it): computed again
    }
  }
  FloatPlanes map = calib::ComputeCorrespondence(reference.view(), reference.points(), view);
  map.attributes[kInputsAttribute] = inputs;
  std::filesystem::create_directories(session_dir + "/correspondence");
  WriteFloatPlanesExr(path, map);
  *seconds += SecondsSince(start);
  return map;
}

}  // namespace acq
