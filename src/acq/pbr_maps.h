// The analytic maps fitted to an SVBRDF map (issue 20; brdf/pbr_model.h): every pixel's
// reconstructed BRDF tabulated at the fit grid's bins, then the analytic model (PbrModel) fitted to
// it, the fit's log-space error kept per pixel.
#pragma once

#include <cstdint>
#include <vector>

#include "acq/validation.h"
#include "brdf/basis.h"
#include "brdf/pbr_model.h"
#include "io/svbrdf_map.h"

namespace acq {

struct PbrMaps {
  int width = 0, height = 0;
  std::vector<PbrParameters> parameters;  // row-major, one a pixel
  std::vector<float> log_rmse;            // the fit's error (PbrFit::log_rmse)
  std::vector<std::uint8_t> converged;    // PbrFit::converged
  std::vector<std::uint8_t> valid;        // the SVBRDF map's valid plane
  double seconds = 0;                     // the fit's wall time
  std::size_t Pixels() const { return parameters.size(); }
};

PbrMaps FitPbrMaps(const SvbrdfMap& map, const BasisView& basis, const PbrFitOptions& options,
                   bool progress);

// The fitted model as a PixelBrdf, for the validation views.
PixelBrdf PbrPixelBrdf(const PbrMaps& maps);

}  // namespace acq
