// The analytic model renderers read (issue 20; docs/export.md), fitted to a pixel's measured
// BRDF so that glTF, MaterialX, Blender and game engines can use a capture:
//
//   f(w_i, w_o) = (1 - max F(w_i . h)) rho_d / pi + F(w_i . h) D(h) G(w_i, w_o) / (4 cos theta_i
//                 cos theta_o)
//
// as glTF's dielectric (KHR_materials_specular's fresnel_mix) takes it: the diffuse is what the
// specular reflection leaves, its share 1 - F at the channel of the largest F (standard_surface
// layers alike). Until 2026-12-03 the diffuse was added whole; on the colour card the two fit
// alike (validation views 1.03 / 1.38 / 1.12x before, 1.05 / 1.38 / 1.12x after), and the
// renderers now take what was fitted.
//
// Lambert diffuse of albedo rho_d; a GGX (Trowbridge-Reitz) specular lobe with alpha =
// roughness^2 (glTF's perceptual roughness), the separable Smith shadowing of GGX, and Schlick's
// Fresnel scaled by the lobe's weight F90, F = F90 (F0' + (1 - F0')(1 - w_i . h)^5), with a colour
// F0' (PbrParameters::f0). Isotropic, as the basis is.
//
// Optionally a coat, as glTF's KHR_materials_clearcoat layers it: a second, white GGX lobe of
// its own roughness with the Fresnel of IOR 1.5 (F0 = 0.04), weight c in [0, 1]:
//
//   f_coated = (1 - c F_coat(w_i . h)) f + c F_coat(w_i . h) D_coat G_coat / (4 cos cos)
//
// Glossy paints and metals have a sharp peak over a broad shoulder, which one lobe cannot follow
// (it fits one and misses the other); with a coat, one lobe takes each (white paint: a sharp
// lobe under a dim, broad coat; docs/export.md). The fit adds it only where it
// lowers the error by kPbrCoatMinGain (docs/export.md: a coat where a pixel needs one).
//
// The fit minimises what the reconstruction minimises: the RMS over the grid of the difference
// of the log-mapped, cos-weighted values (log_mapping.h), so a lobe's peak and the diffuse
// floor count as they do in the method's error (the basis's rho_ref cancels from a difference).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace acq {

struct PbrParameters {
  std::array<double, 3> diffuse{0, 0, 0};  // rho_d, the albedo (R, G, B)
  std::array<double, 3> f0{0, 0, 0};       // F0 / F90: Fresnel at normal incidence, relative
  double roughness = 0.5;                  // perceptual; alpha = roughness^2
  double specular = 1;                     // the lobe's weight: F90 (glTF's specularFactor)
  double coat = 0;                         // the coat's weight c; 0: no coat
  double coat_roughness = 0.1;             // perceptual, as roughness
};

// The fit's bounds, in one place: the writers and the renderers' conventions rely on them.
inline constexpr double kPbrMinRoughness = 0.02;  // alpha 4e-4: sharper than MERL's bins resolve
inline constexpr double kPbrMaxRoughness = 1.0;
inline constexpr double kPbrCoatF0 = 0.04;  // IOR 1.5, fixed by KHR_materials_clearcoat
// The coat is kept only where it lowers the fit's log RMS by this fraction or more: a second lobe
// that buys less models more than the pixel shows.
inline constexpr double kPbrCoatMinGain = 0.1;

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

// The models the fit offers, each adding to the one before (docs/export.md, "The model"):
enum class PbrModel {
  kSchlick,   // Lambert + GGX, Fresnel to 1 at grazing (F90 = 1): 7 parameters
  kWeighted,  // + the lobe's weight, F90 (glTF's specularFactor): 8
  kCoated,    // + a coat, kept where it lowers the error by kPbrCoatMinGain: 10
};
const char* PbrModelName(PbrModel model);  // "schlick", "weighted", "coated"
PbrModel ParsePbrModel(const std::string& name, const std::string& where);  // throws UserError

struct PbrFitOptions {
  // Directions further from the normal are left out of the fit: there the analytic lobe
  // (Schlick's Fresnel towards 1 over 4 cos cos) and measured BRDFs part by orders of
  // magnitude, and with them in, the fit gives up the peak and the diffuse level a render shows.
  // 70 (80 until the coated model): the validation views within 1.5x of the measured map's on
  // every simulated card measured (not on the marbled sample's view 6: 1.74x), where 80 missed
  // the two nearest the highlight by 1.7-2.4x on all but the embossed cards; the
  // price, the fit's error between 70 and 80 degrees up by 4-60% on three pixels scored there
  // (docs/export.md, "The zenith limit").
  double max_zenith_deg = 70;
  int roughness_steps = 16;  // the coarse search over roughness before the joint refinement
  int max_iterations = 100;  // Levenberg-Marquardt, per start
  PbrModel model = PbrModel::kCoated;
  void Check() const;  // throws UserError
};

struct PbrFit {
  PbrParameters parameters;
  double log_rmse = 0;           // over the grid's bins and the three channels, log-mapped space
  double uncoated_log_rmse = 0;  // the same without a coat (== log_rmse when none was tried)
  bool converged = false;        // false: the target had no finite value, or the refinement ran out
  int iterations = 0;
};

// Fits the model to a target BRDF given at the grid's bins (`target`: Size() x 3, R G B per
// bin, 1/sr). Never returns NaN: non-finite targets are left out, and a target with none finite
// gives zero parameters, log_rmse 0 and converged false.
PbrFit FitPbr(const PbrFitGrid& grid, const float* target, const PbrFitOptions& options);

}  // namespace acq
