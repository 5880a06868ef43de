// The basis at an arbitrary light/view pair (not only at bin centres): what a pixel whose true
// directions fall between bins reconstructs with. Nearest bin (MERL's own binning) or trilinear
// interpolation between the 8 surrounding bin centres, in the grid's index coordinates
// (sqrt-spaced theta_h; phi_d periodic over [0, pi) by reciprocity). Masked bins take no part;
// the weights of the valid ones are renormalised.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

#include "brdf/basis.h"
#include "core/rusinkiewicz.h"

namespace acq {

enum class RowLookup { kNearest, kInterpolated };
// The names plans, maps and the CLI use ("nearest", "interpolated"); nullopt for another name.
const char* RowLookupName(RowLookup lookup);
std::optional<RowLookup> ParseRowLookup(const std::string& name);

struct BasisSample {
  float mean = 0, ref = 0;  // mu and rho_ref at the directions
  float cos_weight = 0;     // merl::CosWeight of the true directions (not of a bin centre)
};

// Writes the first k entries of the row at the directions (sample frame, unit vectors, both
// above the horizon) into `row`. Returns false when no valid bin contributes.
bool SampleBasis(const BasisView& basis, const Eigen::Vector3d& in, const Eigen::Vector3d& out,
                 int k, RowLookup lookup, float* row, BasisSample* sample);
// The same from the directions' isotropic Rusinkiewicz angles and cos weight (merl::CosWeight),
// for callers that computed them already (the batched per-pixel solve, many at once).
bool SampleBasisAt(const BasisView& basis, const RusinkiewiczAngles& angles, double cos_weight,
                   int k, RowLookup lookup, float* row, BasisSample* sample);

// The BRDF (1/sr, RGB) that per-channel coefficients (3 x k, R then G then B) describe, at the
// directions: x = q . c + mu, then the inverse log mapping with the true directions' cos weight.
// Zero below the horizon or where no valid bin contributes.
std::array<double, 3> BrdfFromCoefficients(const BasisView& basis, const float* coefficients, int k,
                                           const Eigen::Vector3d& in, const Eigen::Vector3d& out,
                                           RowLookup lookup);

}  // namespace acq
