// Scoring an SVBRDF map against known materials (synthetic inputs, the simulated instrument):
// every pixel's reconstruction Q_k c + mu against its true material's table, as log-space RMSE
// over all valid bins of the MERL grid (the error of the homogeneous evaluations, brdf/
// evaluation.h, per pixel).
#pragma once

#include <array>
#include <vector>

#include "core/gantry_geometry.h"

#include "brdf/basis.h"
#include "brdf/merl_brdf.h"
#include "io/svbrdf_map.h"

namespace acq {

struct MapScore {
  long pixels = 0, valid = 0;
  double median_log_rmse = 0;                       // over every pixel channel of the map
  double median_log_rmse_valid = 0;                 // over the pixels the map marks valid
  std::vector<float> log_rmse;                      // per pixel, mean over its channels
  std::vector<double> material_median_log_rmse;     // per true material, over its pixels
  std::array<double, 3> channel_median_log_rmse{};  // R, G, B over every pixel
  // The diffuse colour (pi f at DiffuseColourDirections(), as a reflectance) of each pixel
  // against its material's, CIEDE2000 (core/colour.h): median over the pixels.
  double albedo_delta_e2000_median = 0;
  // Per true material: the median of its pixels' CIEDE2000 (as above), and the CIEDE2000 of its
  // pixels' mean diffuse colour: a bias (a colour calibration's, a basis's) shows in the second,
  // the per-pixel fit's noise only in the first.
  std::vector<double> material_albedo_delta_e2000_median, material_albedo_mean_delta_e2000;
};

// The map's normals against the true ones (issue 19): the median angular error over the relief
// (pixels whose true tilt is over 0.5 degree), beside the same for the sample's normal assumed,
// and the median false tilt on flat areas (true tilt under 0.05 degree); NaN where none.
struct NormalScore {
  double median_error_deg_relief = 0, median_error_deg_relief_assumed_flat = 0;
  double median_tilt_deg_flat = 0;
  long relief_pixels = 0, flat_pixels = 0, refused = 0, no_evidence = 0;
  // With labels: the relief split into pixels of one material all around (kInkEdgeReach) and
  // pixels near an edge between materials, whose views mix two materials and two slopes (an
  // embossed print is steepest where its ink ends).
  double median_error_deg_relief_one_material = 0, median_error_deg_relief_ink_edges = 0;
  long relief_pixels_one_material = 0, relief_pixels_ink_edges = 0;
  // With labels, per true material (by label): the median false tilt over its flat pixels (NaN
  // where it has none). A search that tilts one material's flat patch shows here, where the
  // median over the whole sample hides it.
  std::vector<double> material_median_tilt_deg_flat;
  // The estimated pixels' uncertainty (the map's normal_uncertainty_deg): its median, and the
  // relief's estimated pixels split at kCertainNormalDeg: how well the uncertainty foretells
  // the error (NaN where none).
  double median_uncertainty_deg = 0;
  double median_error_deg_relief_certain = 0, median_error_deg_relief_uncertain = 0;
  long relief_pixels_certain = 0, relief_pixels_uncertain = 0;
  std::vector<float> error_deg;  // per map pixel, row-major: the estimate's angle to the truth
};
// How far (map pixels) another material makes a pixel an ink edge's: a view 65 degrees off the
// normal sees a map pixel's point through a camera pixel 2.4 map pixels long.
constexpr int kInkEdgeReach = 2;
// NormalScore's split of the relief by the estimate's uncertainty (degrees).
constexpr double kCertainNormalDeg = 1;
// `truth[pixel]`: the true normal (sample frame, unit) of each map pixel, row-major; `labels`
// (optional, same order): the true material, for the split by ink edges.
NormalScore ScoreNormals(const SvbrdfMap& map, const std::vector<Eigen::Vector3f>& truth,
                         const std::vector<int>& labels = {});

// Where the diffuse colour is read: light 45 degrees from the normal, camera along it, away
// from the specular lobe (the half vector 22.5 degrees off the normal).
DirectionPair DiffuseColourDirections();

// `label[pixel]` indexes `truth`; negative: no truth there (not scored). Throws UserError when
// the sizes disagree or the basis has fewer components than the map.
MapScore ScoreMap(const SvbrdfMap& map, const BasisView& basis, const std::vector<int>& label,
                  const std::vector<MerlBrdf>& truth);

}  // namespace acq
