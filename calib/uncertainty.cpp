#include "calib/uncertainty.h"

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace acq::calib {

Eigen::Vector2d ReprojectThroughFrames(const BoardProblem& from, const BoardProblem& to,
                                       const Eigen::Vector2d& q, double distance_mm) {
  const Eigen::Vector3d p_in_cam = from.camera().Unproject(q) * distance_mm;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int f = 0; f < from.Frames(); ++f) {
    const Eigen::Vector3d p_in_board = from.cam_from_board()[f].Inverse() * p_in_cam;
    mean += to.cam_from_board()[f] * p_in_board;
  }
  return to.camera().Project(mean / from.Frames());
}

double MedianBoardDistance(const BoardProblem& problem) {
  std::vector<double> d;
  for (const Pose& p : problem.cam_from_board()) d.push_back((p * problem.board().Centre()).norm());
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

UncertaintyModel::UncertaintyModel(const BoardProblem& solved, const Selections& selections,
                                   double sigma_px)
    : problem_(solved), selections_(selections) {
  const Eigen::MatrixXd J = problem_.Jacobian(selections_);
  const Eigen::MatrixXd J_obs = J.topRows(problem_.BoardMeasurements());
  const Eigen::LDLT<Eigen::MatrixXd> JtJ(J.transpose() * J);
  const Eigen::MatrixXd M_Jobs_t = JtJ.solve(J_obs.transpose());  // M J_obs^T
  cov_b_ = sigma_px * sigma_px * M_Jobs_t * M_Jobs_t.transpose();
}

Eigen::Matrix2d UncertaintyModel::Covariance(const Eigen::Vector2d& q, double distance_mm) const {
  // The baseline carries the point into the board frames; the perturbed solution brings it back.
  const Eigen::MatrixXd dq_db =
      problem_.PackedDerivative(selections_, [&](const BoardProblem& perturbed) {
        return Eigen::VectorXd(ReprojectThroughFrames(problem_, perturbed, q, distance_mm));
      });
  return dq_db * cov_b_ * dq_db.transpose();
}

double UncertaintyModel::WorstStdev(const Eigen::Vector2d& q, double distance_mm) const {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(Covariance(q, distance_mm));
  return std::sqrt(std::max(0.0, eig.eigenvalues()(1)));
}

}  // namespace acq::calib
