#include "brdf/reconstruct.h"

#include <Eigen/Dense>
#include <limits>

#include "core/error.h"

namespace acq {

void RidgeOptions::Check(const BasisView& basis) const {
  if (components < 1 || components > basis.components)
    throw UserError("--k",
                    "must be in [1, " + std::to_string(basis.components) +
                        "] (components stored in the basis), got " + std::to_string(components),
                    "rebuild the basis with more --components or ask for fewer");
  if (!(eta >= 0)) throw UserError("--eta", "must be >= 0", "the papers use 40");
}

Eigen::MatrixXd SampledRows(const BasisView& basis, const std::vector<std::size_t>& bins, int k) {
  Eigen::MatrixXd qs(Eigen::Index(bins.size()), k);
  for (std::size_t r = 0; r < bins.size(); ++r) {
    const float* row = basis.Row(bins[r]);
    for (int c = 0; c < k; ++c) qs(Eigen::Index(r), c) = row[c];
  }
  return qs;
}

Eigen::VectorXd SampledMean(const BasisView& basis, const std::vector<std::size_t>& bins) {
  Eigen::VectorXd mu(Eigen::Index(bins.size()));
  for (std::size_t r = 0; r < bins.size(); ++r) mu(Eigen::Index(r)) = basis.mean[bins[r]];
  return mu;
}

Eigen::VectorXd RidgeSolve(const Eigen::MatrixXd& qs, const Eigen::VectorXd& xs_minus_mu,
                           double eta) {
  Eigen::MatrixXd normal = qs.transpose() * qs;
  normal.diagonal().array() += eta;
  // LDLT also copes with eta = 0 and n < k (semi-definite); the caller warns via the condition.
  return normal.ldlt().solve(qs.transpose() * xs_minus_mu);
}

double ConditionNumber(const Eigen::MatrixXd& qs) {
  // With n < k the smallest k - n singular values are exactly zero.
  if (qs.rows() < qs.cols() || qs.cols() == 0) return std::numeric_limits<double>::infinity();
  // Eigenvalues of the k x k normal matrix are the squared singular values: several times
  // cheaper than an SVD and exact enough for condition numbers up to ~1e7, all that matters.
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(qs.transpose() * qs, Eigen::EigenvaluesOnly)
          .eigenvalues();
  if (!(ev(0) > 0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(ev(ev.size() - 1) / ev(0));
}

double ConditionOfBins(const BasisView& basis, const std::vector<std::size_t>& bins, int k) {
  if (int(bins.size()) < k) return std::numeric_limits<double>::infinity();
  return ConditionNumber(SampledRows(basis, bins, k));
}

}  // namespace acq
