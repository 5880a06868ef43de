#include "calib/extrinsics.h"

#include <cmath>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include "calib/board_problem.h"
#include "core/angles.h"
#include "core/error.h"

namespace acq::calib {

Pose SampleFromBoard(const BoardSpec& board) {
  // x_s = Rx(pi) (x_b - centre): (x, y, z) -> (x - cx, -(y - cy), -z).
  Pose p;
  p.r = {M_PI, 0, 0};
  p.t = p.R() * -board.Centre();
  return p;
}

namespace {

double RotationAngle(const Pose& a, const Pose& b) {
  const Eigen::AngleAxisd d(a.R().transpose() * b.R());
  return std::abs(d.angle());
}

ExtrinsicsResult SolveOrdering(const CameraModel& camera, const BoardSpec& board,
                               const BoardObservation& obs) {
  // Seed: PnP on the corners' unprojected rays (an ideal pinhole of unit focal length), so the
  // lens model's distortion is honoured exactly.
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  std::vector<Eigen::Vector2d> q;
  std::vector<int> index;
  for (std::size_t i = 0; i < obs.corners.size(); ++i)
    if (obs.corners[i].z() > 0) {
      q.push_back(obs.corners[i].head<2>());
      index.push_back(static_cast<int>(i));
    }
  const std::vector<Eigen::Vector3d> rays = camera.Unproject(q);
  for (std::size_t k = 0; k < rays.size(); ++k) {
    object.emplace_back(corners[index[k]].x(), corners[index[k]].y(), 0.f);
    image.emplace_back(rays[k].x() / rays[k].z(), rays[k].y() / rays[k].z());
  }
  cv::Vec3d rvec, tvec;
  cv::solvePnP(object, image, cv::Matx33d::eye(), cv::noArray(), rvec, tvec);
  Pose seed;
  seed.r = {rvec[0], rvec[1], rvec[2]};
  seed.t = {tvec[0], tvec[1], tvec[2]};

  BoardProblem problem(camera, board, {obs}, {seed});
  Selections s;
  s.core = s.distortions = false;
  s.regularization = false;
  s.outlier_rejection = true;
  problem.Optimize(s);
  ExtrinsicsResult r;
  r.cam_from_sample = problem.cam_from_board()[0].Compose(SampleFromBoard(board).Inverse());
  r.rms_px = problem.RmsPerCoordinate(&r.corners);
  return r;
}

}  // namespace

ExtrinsicsResult SolveCamFromSample(const CameraModel& camera, const BoardSpec& board,
                                    const BoardObservation& observation,
                                    const std::optional<Pose>& expected) {
  if (observation.DetectedCorners() < 4)
    throw UserError(observation.image.empty() ? "extrinsics" : observation.image,
                    "the board is not found (fewer than 4 corners detected)",
                    "check the board lies flat in view and --board gives its inner corners");
  if (!expected) return SolveOrdering(camera, board, observation);
  ExtrinsicsResult best;
  best.angle_from_expected_deg = 1e9;
  const std::vector<std::vector<int>> symmetries = BoardSymmetries(board);
  for (std::size_t k = 0; k < symmetries.size(); ++k) {
    BoardObservation reordered = observation;
    for (std::size_t i = 0; i < symmetries[k].size(); ++i)
      reordered.corners[i] = observation.corners[symmetries[k][i]];
    ExtrinsicsResult r = SolveOrdering(camera, board, reordered);
    r.symmetry = static_cast<int>(k);
    r.angle_from_expected_deg = RadToDeg(RotationAngle(r.cam_from_sample, *expected));
    if (r.angle_from_expected_deg < best.angle_from_expected_deg) best = r;
  }
  return best;
}

}  // namespace acq::calib
