// One stationary camera observing a chessboard in several poses: the inputs of mrcal_optimize()
// owned in one place, with the solve, the residuals and the Jacobian. Every call into mrcal's
// optimizer goes through here. The reference frame is the camera's (cam_from_ref = identity);
// frame f's pose is cam_from_board[f] (mrcal's frames_toref).
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "calib/board.h"
#include "calib/camera_model.h"
#include "calib/corners.h"

namespace acq::calib {

struct Selections {
  bool core = true, distortions = true, frames = true, warp = false;
  bool regularization = true, outlier_rejection = true;
  mrcal_problem_selections_t ToMrcal() const;
};

class BoardProblem {
 public:
  // Takes the found boards of `images` (those with corners), in order.
  BoardProblem(CameraModel camera, const BoardSpec& board,
               const std::vector<BoardObservation>& images, std::vector<Pose> cam_from_board);

  // Solve with these variables free; the others stay at their current values. Marks new
  // outliers (weight < 0) in the observation pool when outlier rejection is on.
  void Optimize(const Selections& selections);

  // The measurement vector x at the current values (boards first, 2 per corner, weighted; then
  // regularization), for `selections`. The board is the one solved for: bowed by warp() whether
  // or not `selections` frees the warp (zero until a solve frees it).
  std::vector<double> Measurements(const Selections& selections) const;
  int BoardMeasurements() const;  // leading entries of Measurements() that are board residuals

  // df/db of any function of the problem, in mrcal's packed (unitless) state, by central
  // differences: column i is the derivative by packed state element i.
  Eigen::MatrixXd PackedDerivative(
      const Selections& selections,
      const std::function<Eigen::VectorXd(const BoardProblem&)>& f) const;
  // dx/db: PackedDerivative of Measurements().
  Eigen::MatrixXd Jacobian(const Selections& selections) const;
  int States(const Selections& selections) const;

  const CameraModel& camera() const { return camera_; }
  CameraModel& camera() { return camera_; }
  const BoardSpec& board() const { return board_; }
  const std::vector<Pose>& cam_from_board() const { return frames_; }
  std::vector<Pose>& cam_from_board() { return frames_; }
  Eigen::Vector2d warp() const { return {warp_.x2, warp_.y2}; }
  // Observation pool: frames x corners, (x, y, weight); weight < 0: missing or outlier.
  const std::vector<mrcal_point3_t>& pool() const { return pool_; }
  int Frames() const { return static_cast<int>(frames_.size()); }
  int Outliers() const;  // corners detected but rejected by the solver
  // Per-corner reprojection errors (pixels, unweighted) at the current values; NaN for corners
  // that are missing or outliers. Frames x corners x 2.
  std::vector<double> Residuals() const;
  // RMS of Residuals() per coordinate over the inlier corners, whose count goes to `inliers`.
  double RmsPerCoordinate(int* inliers = nullptr) const;
  // The camera with lens model changed: intrinsics extended with small seeds (as mrcal's tool
  // seeds them: the rational terms near zero so the model starts as its simpler self).
  void ChangeLensModel(const std::string& lensmodel);

 private:
  Eigen::VectorXd StateScale(const Selections& selections) const;  // packed -> unpacked
  void ApplyState(const Selections& selections, const std::vector<double>& unpacked);
  std::vector<double> CurrentState(const Selections& selections) const;

  CameraModel camera_;
  BoardSpec board_;
  std::vector<Pose> frames_;
  std::vector<mrcal_point3_t> pool_;
  std::vector<mrcal_observation_board_t> observations_;
  mrcal_calobject_warp_t warp_{};
  int initially_missing_ = 0;
};

}  // namespace acq::calib
