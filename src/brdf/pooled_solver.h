// The pooled per-pixel solve (docs/reconstruction.md, "Pooled"): every pixel is solved twice
// from its own rows, alone (the independent ridge towards the mean, as SolvePixels) and with a
// ridge of the model's strength towards its group's centre,
//   c = c_g + d,  d = (Q_k^T Q_k + lambda I)^-1 Q_k^T (y - Q c_g),
// the group being the one of the three nearest in feature space whose centre explains the
// pixel's observations best. The pixel keeps whichever of the two predicts its own views better
// when each view is left out in turn (exact for a ridge: r_v / (1 - h_v)): where its data
// disagree with the group (a mixed pixel on an ink boundary, a stroke too thin to be in the
// sample), the prior loses to the data and the pixel is its independent solve.
#pragma once

#include "brdf/pixel_solver.h"
#include "brdf/pooled_model.h"

namespace acq {

// Whether a pixel its group's centre explains takes the prior.
enum class PriorChoice {
  kByLeftOutViews,  // where it predicts the left-out views better than the pixel alone (above)
  kWhereExplained,  // always: a pixel whose normal was judged by a centre (normal_search.h)
};

// `solution` is sized for model.components coefficients per channel. With a model without
// groups every pixel is its independent solve. Never writes NaN.
void SolvePixelsPooled(const BasisView& basis, const PixelObservations& observations,
                       const PooledModel& model, const PixelSolveOptions& options,
                       PixelSolution* solution, int first_pixel = 0,
                       PriorChoice choice = PriorChoice::kByLeftOutViews);

}  // namespace acq
