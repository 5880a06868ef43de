// Projection uncertainty of a solved calibration, as mrcal defines it
// (mrcal.secretsauce.net/uncertainty.html): observation noise sigma moves the optimum by
// db = M J_obs^T dx with M = (J^T J)^-1, so Var(b) = sigma^2 M J_obs^T J_obs M; a pixel q is
// unprojected to a point at `distance`, carried into every board frame with the baseline
// solution, brought back with the perturbed one and averaged ("mean-frames"), and projected;
// Var(q) = dq/db Var(b) dq/db^T. Jacobians are numerical in mrcal's packed state.
#pragma once

#include <Eigen/Core>

#include "calib/board_problem.h"

namespace acq::calib {

class UncertaintyModel {
 public:
  // `solved`: at its optimum for `selections`. sigma: observed pixel noise per coordinate
  // (the RMS of the inlier residual coordinates is the usual estimate).
  UncertaintyModel(const BoardProblem& solved, const Selections& selections, double sigma_px);

  // 2x2 covariance of the projection of pixel q at `distance_mm` from the camera.
  Eigen::Matrix2d Covariance(const Eigen::Vector2d& q, double distance_mm) const;
  // sqrt of the covariance's largest eigenvalue: the worst-direction standard deviation (px).
  double WorstStdev(const Eigen::Vector2d& q, double distance_mm) const;

 private:
  BoardProblem problem_;
  Selections selections_;
  Eigen::MatrixXd cov_b_;  // packed state
};

// The mean-frames reprojection: pixel q unprojected by `from` at distance_mm, carried into each
// board frame by `from`'s poses, back by `to`'s, averaged, projected by `to`'s camera. With
// `from` the truth and `to` a solve, the result minus q is the solve's projection error.
Eigen::Vector2d ReprojectThroughFrames(const BoardProblem& from, const BoardProblem& to,
                                       const Eigen::Vector2d& q, double distance_mm);

// Median distance of the boards' centres from the camera.
double MedianBoardDistance(const BoardProblem& problem);

}  // namespace acq::calib
