// Ridge reconstruction (docs/architecture.md; Yu et al. eq. 3):
//   c = (Qs^T Qs + eta I)^-1 Qs^T (xs - mus),  x = Q c + mu,
// with Qs the basis rows at the n observed directions (first k columns).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "brdf/basis.h"

namespace acq {

struct RidgeOptions {
  int components = kDefaultComponents;       // k; NJR15 uses k = n
  double eta = kDefaultEta;                  // meaningful with components scaled by singular values
  void Check(const BasisView& basis) const;  // throws UserError
};

// The first k columns of the basis rows at the given bins (n x k), and mu there.
Eigen::MatrixXd SampledRows(const BasisView& basis, const std::vector<std::size_t>& bins, int k);
Eigen::VectorXd SampledMean(const BasisView& basis, const std::vector<std::size_t>& bins);

// Coefficients for one channel from mapped observations xs (n) at rows qs (n x k).
Eigen::VectorXd RidgeSolve(const Eigen::MatrixXd& qs, const Eigen::VectorXd& xs_minus_mu,
                           double eta);

// Condition number of qs (ratio of extreme singular values; infinite if rank deficient or
// n < k), and of the first k columns of the basis rows at `bins`.
double ConditionNumber(const Eigen::MatrixXd& qs);
double ConditionOfBins(const BasisView& basis, const std::vector<std::size_t>& bins, int k);

}  // namespace acq
