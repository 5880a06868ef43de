// Choosing light/view directions (NJR15, as its authors' code does it; Yu et al. Sec. 3.2):
// minimise the condition number of the sampled basis rows Qs (n x k), growing the set one
// direction at a time. The first direction is the allowed row of largest norm; each new one is
// the best of many random allowed candidates; after each addition a local search moves each
// direction one bin along each grid axis (theta_h, theta_d, phi_d) while the condition number
// falls. With k = n (the default) the set of j directions is scored with its first j columns.
//
// Beyond the papers: with a near-field geometry the score is the worst (or mean) condition
// number over positions across the sample, each position with the rows of its own true
// directions, so the set is good at the edges of the field of view, not only at its centre.
#pragma once

#include <cstdint>
#include <vector>

#include "brdf/basis.h"
#include "brdf/directions.h"
#include "brdf/reconstruct.h"
#include "core/gantry_geometry.h"

namespace acq {

enum class FovObjective { kWorst, kMean };

// What a set of directions is scored by.
//  kCondition: the condition number of Qs (NJR15, Yu et al.).
//  kExpectedError: the expected log-space reconstruction error over the basis's own prior,
//    E||Q_k c_hat - (x - mu)||^2 with x - mu = Q v over all stored components and E[v v^T] = I/m
//    (what the training set's coefficients satisfy). It counts what the condition number
//    cannot: how the components beyond k, seen at the sampled directions, leak into the k
//    estimated ones through the ridge solve. Sets with a fine condition number can still leak.
//    Only sets whose condition number stays under max_condition compete on it; the others rank
//    behind them by condition number, so the result keeps NJR15's stability guarantee.
enum class Score { kCondition, kExpectedError };

struct OptimizerOptions {
  int n = 20;
  int k = 0;              // components scored; 0 means k = n
  int candidates = 1000;  // random candidates per added direction
  std::uint64_t seed = 1;
  DirectionConstraints constraints;
  // Field-of-view awareness: off when geometry.sample_size_mm == 0.
  NearFieldGeometry geometry;
  int fov_grid = 3;  // fov_grid x fov_grid positions scored, corner to corner (3: centre,
                     // edge midpoints and corners)
  FovObjective fov_objective = FovObjective::kWorst;
  Score score = Score::kExpectedError;
  double eta = kDefaultEta;    // the ridge strength the expected error is computed for
  double max_condition = 200;  // cap for kExpectedError (the seed's 20 have 664 on our basis)
  bool progress = true;

  int EffectiveK() const { return k > 0 ? k : n; }
  void Check(const BasisView& basis) const;  // throws UserError
};

struct OptimizedDirections {
  std::vector<Direction> directions;  // bin centres, phi_h = 0
  double condition = 0;               // condition number (worst/mean over the field of view)
  double expected_error = 0;          // only with Score::kExpectedError
  double seconds = 0;
};

OptimizedDirections OptimizeDirections(const BasisView& basis, const OptimizerOptions& options);

}  // namespace acq
