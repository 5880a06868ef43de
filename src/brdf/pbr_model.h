// The analytic model renderers read (issue 20; docs/export.md), fitted to a pixel's measured
// BRDF so that glTF, MaterialX, Blender and game engines can use a capture:
//
//   f(w_i, w_o) = rho_d / pi + F(w_i . h) D(h) G(w_i, w_o) / (4 cos theta_i cos theta_o)
//
// Lambert diffuse of albedo rho_d; a GGX (Trowbridge-Reitz) specular lobe with alpha =
// roughness^2 (glTF's perceptual roughness), the separable Smith shadowing of GGX, and Schlick's
// Fresnel F = F0 + (1 - F0)(1 - w_i . h)^5 with a colour F0. Isotropic, as the basis is.
//
// The fit minimises what the reconstruction minimises: the RMS over the grid of the difference
// of the log-mapped, cos-weighted values (log_mapping.h), so a lobe's peak and the diffuse
// floor count as they do in the method's error (the basis's rho_ref cancels from a difference).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace acq {

struct PbrParameters {
  std::array<double, 3> diffuse{0, 0, 0};  // rho_d, the albedo (R, G, B)
  std::array<double, 3> f0{0, 0, 0};       // specular reflectance at normal incidence
  double roughness = 0.5;                  // perceptual; alpha = roughness^2
};

// The fit's bounds, in one place: the writers and the renderers' conventions rely on them.
inline constexpr double kPbrMinRoughness = 0.02;  // alpha 4e-4: sharper than MERL's bins resolve
inline constexpr double kPbrMaxRoughness = 1.0;

// f (1/sr, R G B) at directions in the sample frame (z along the normal); 0 below the horizon.
std::array<double, 3> EvaluatePbr(const PbrParameters& p, const Eigen::Vector3d& in,
                                  const Eigen::Vector3d& out);

// Where the fit compares: MERL bins spread evenly in index over the valid grid (so as dense near
// the specular peak as MERL's sqrt-spaced theta_h is), with each bin's geometry at its centre.
struct PbrFitGrid {
  std::vector<std::uint32_t> bins;  // flat MERL indices, ascending
  std::vector<double> cos_in, cos_out, cos_h, cos_d, cos_weight;
  std::size_t Size() const { return bins.size(); }
  // The default grid over the bins that `valid` (kBins entries, a basis's mask) marks, with
  // both directions within `max_zenith` (radians) of the normal.
  static PbrFitGrid Default(const std::uint8_t* valid, double max_zenith);
};

struct PbrFitOptions {
  // Directions further from the normal are left out of the fit: there the analytic lobe
  // (Schlick's Fresnel towards 1 over 4 cos cos) and measured BRDFs part by orders of
  // magnitude, and with them in, the fit gives up the peak and the diffuse level a render shows
  // (measured: docs/export.md).
  double max_zenith_deg = 80;
  int roughness_steps = 16;  // the coarse search over roughness before the joint refinement
  int max_iterations = 30;   // Levenberg-Marquardt on all seven parameters
  void Check() const;        // throws UserError
};

struct PbrFit {
  PbrParameters parameters;
  double log_rmse = 0;     // over the grid's bins and the three channels, log-mapped space
  bool converged = false;  // false: the target had no finite value, or the refinement ran out
  int iterations = 0;
};

// Fits the model to a target BRDF given at the grid's bins (`target`: Size() x 3, R G B per
// bin, 1/sr). Never returns NaN: non-finite targets are left out, and a target with none finite
// gives zero parameters, log_rmse 0 and converged false.
PbrFit FitPbr(const PbrFitGrid& grid, const float* target, const PbrFitOptions& options);

}  // namespace acq
