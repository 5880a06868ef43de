#include "calib/intrinsics_solve.h"

#include <chrono>
#include <cmath>

#include <opencv2/calib3d.hpp>

#include "core/angles.h"
#include "core/error.h"

namespace acq::calib {

void IntrinsicsOptions::Check() const {
  LensModelParams(lensmodel, "--lensmodel");
  if (focal_px < 0) throw UserError("--focal-px", "must be positive (or omitted to estimate it)");
  if (min_boards < 3) throw UserError("min_boards", "a calibration needs at least 3 boards");
}

namespace {

struct BoardPoints {
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
};

BoardPoints DetectedPoints(const BoardSpec& board, const BoardObservation& obs) {
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard();
  BoardPoints out;
  for (std::size_t i = 0; i < obs.corners.size(); ++i)
    if (obs.corners[i].z() > 0) {
      out.object.emplace_back(corners[i].x(), corners[i].y(), 0.f);
      out.image.emplace_back(obs.corners[i].x(), obs.corners[i].y());
    }
  return out;
}

}  // namespace

double EstimateFocalPx(int width, int height, const BoardSpec& board,
                       const std::vector<BoardObservation>& images) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (const BoardObservation& obs : images) {
    if (!obs.found()) continue;
    BoardPoints p = DetectedPoints(board, obs);
    if (p.object.size() < 4) continue;
    object.push_back(std::move(p.object));
    image.push_back(std::move(p.image));
  }
  const cv::Mat K = cv::initCameraMatrix2D(object, image, cv::Size(width, height));
  return 0.5 * (K.at<double>(0, 0) + K.at<double>(1, 1));
}

std::string SplinedModelFor(int width, double focal_px, int nx, int ny) {
  // The spline must cover the whole imager: the horizontal field of view plus 10%.
  const int fov_x_deg =
      static_cast<int>(std::ceil(1.1 * RadToDeg(2 * std::atan(0.5 * width / focal_px))));
  return "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=" + std::to_string(nx) +
         "_Ny=" + std::to_string(ny) + "_fov_x_deg=" + std::to_string(fov_x_deg);
}

IntrinsicsSolution SolveIntrinsics(int width, int height, const BoardSpec& board,
                                   const std::vector<BoardObservation>& images,
                                   const IntrinsicsOptions& options) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  std::vector<BoardObservation> used;
  std::vector<int> image_of_frame;
  for (std::size_t i = 0; i < images.size(); ++i)
    if (images[i].found() && images[i].DetectedCorners() >= 4) {
      used.push_back(images[i]);
      image_of_frame.push_back(static_cast<int>(i));
    }
  if (static_cast<int>(used.size()) < options.min_boards)
    throw UserError("calibration",
                    "only " + std::to_string(used.size()) + " of " + std::to_string(images.size()) +
                        " images show a " + std::to_string(board.width_n) + "x" +
                        std::to_string(board.height_n) + " board; at least " +
                        std::to_string(options.min_boards) + " are needed",
                    used.empty() ? "check --board: it counts inner corners (where four squares "
                                   "meet), e.g. a board of 10 x 7 squares is 9x6"
                                 : "take more images, the board filling the view at varied tilts");

  // Pinhole seed: focal length, the imager centre, and each board's pose by PnP.
  const double focal =
      options.focal_px > 0 ? options.focal_px : EstimateFocalPx(width, height, board, used);
  const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  const cv::Matx33d K(focal, 0, cx, 0, focal, cy, 0, 0, 1);
  std::vector<Pose> frames;
  for (const BoardObservation& obs : used) {
    const BoardPoints p = DetectedPoints(board, obs);
    cv::Vec3d rvec, tvec;
    cv::solvePnP(p.object, p.image, K, cv::noArray(), rvec, tvec);
    Pose pose;
    pose.r = {rvec[0], rvec[1], rvec[2]};  // OpenCV's rvec is mrcal's r: both Rodrigues
    pose.t = {tvec[0], tvec[1], tvec[2]};
    frames.push_back(pose);
  }
  BoardProblem problem(CameraModel("LENSMODEL_PINHOLE", {focal, focal, cx, cy}, width, height),
                       board, used, frames);

  Selections s;
  s.core = false;
  s.distortions = false;
  s.regularization = false;
  s.outlier_rejection = false;
  problem.Optimize(s);  // geometry only
  s.core = true;
  problem.Optimize(s);  // and the pinhole core

  problem.ChangeLensModel(options.lensmodel);
  const bool splined = options.lensmodel.rfind("LENSMODEL_SPLINED", 0) == 0;
  // A spline's core is nearly redundant with its control points: mrcal's tool locks it.
  s.core = !splined;
  s.distortions = options.lensmodel != "LENSMODEL_PINHOLE";
  s.regularization = true;
  s.outlier_rejection = options.outlier_rejection;
  problem.Optimize(s);
  if (options.board_warp) {
    s.warp = true;
    problem.Optimize(s);
  }

  IntrinsicsSolution out{std::move(problem), s, std::move(image_of_frame)};
  out.rms_per_coordinate = out.problem.RmsPerCoordinate(&out.inliers);
  out.rms_per_point = std::sqrt(2.0) * out.rms_per_coordinate;
  out.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace acq::calib
