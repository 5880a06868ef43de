// Using an SVBRDF map (Yu et al. Figs. 1 and 5): the sample re-rendered under any light and
// camera arm pose (validation views, in reference-view pixels), spheres lit by a point light
// with the BRDF of chosen pixels, a pixel's BRDF as a MERL table, and quick-look maps.
#pragma once

#include <string>
#include <vector>

#include "brdf/basis_rows.h"
#include "brdf/merl_brdf.h"
#include "core/gantry_geometry.h"
#include "io/svbrdf_map.h"

namespace acq {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // row-major, 3 floats a pixel, linear
};

// The map's coefficients of a pixel, R then G then B (3 x k), as BrdfFromCoefficients takes them.
std::vector<float> PixelCoefficients(const SvbrdfMap& map, int x, int y);

// The pixel's BRDF as a measurement in the sample frame sees it: its coefficients describe the
// BRDF in its facet's frame (the map's normal; core/facet_frame.h), so the directions are turned
// into that frame and the value scaled by (n . l) / l.z; 0 where the facet turns from the light
// or the view. For a pixel with the sample's normal, simply its BRDF. Where the map records a
// camera pixel's spread (SvbrdfMapInfo::pixel_spread_px) and the pixel's neighbours' normals
// differ, the mean over a box of that spread, the normal changing linearly as its neighbours'
// do, read in parts of at most 0.25 degree of turn, and at its own normal past 4 degrees of turn
// across the box (docs/reconstruction.md, "A camera pixel's footprint in the map's renders"):
// what a camera whose pixel straddles facets records.
std::array<double, 3> MapBrdfAt(const SvbrdfMap& map, const BasisView& basis, int x, int y,
                                const Eigen::Vector3d& in, const Eigen::Vector3d& out,
                                RowLookup lookup);

// Relative radiance of every reference pixel for a light of unit intensity at the arms' light
// pose and the camera at theirs, each pixel with its own near-field directions:
// L = rho(w_i, w_o) cos(theta_i) / r_light^2 (scaled so a light at 1 m gives rho cos).
RgbImage RenderView(const SvbrdfMap& map, const BasisView& basis, const ArmAngles& arms,
                    const NearFieldGeometry& geometry, RowLookup lookup);

// The BRDF at one far-field configuration for every pixel: quick-look maps.
RgbImage RenderConfiguration(const SvbrdfMap& map, const BasisView& basis,
                             const DirectionPair& directions, RowLookup lookup);

// One sphere a pixel, side by side, each `size` pixels across, seen orthographically from +z
// and lit from `light` (a direction): L = rho cos(theta_i). Pixels as (x, y) in the map.
RgbImage RenderSpheres(const SvbrdfMap& map, const BasisView& basis,
                       const std::vector<std::pair<int, int>>& pixels, const Eigen::Vector3d& light,
                       int size, RowLookup lookup);

// A pixel's reconstructed BRDF tabulated on the MERL grid (masked bins -1).
MerlBrdf PixelAsMerl(const SvbrdfMap& map, const BasisView& basis, int x, int y);

// The row lookup a map was reconstructed with (its acqRowLookup attribute).
RowLookup MapRowLookup(const SvbrdfMap& map);

// The exposure that puts the 99th percentile of `values` at 0.9 (1 when that is not positive):
// the scale of every PNG made from linear values.
double AutoExposure(std::vector<float> values);

// Linear image to an 8-bit sRGB PNG; `exposure` scales first, 0 picks AutoExposure of all its
// values. Throws UserError naming the file when it cannot be written.
void WritePng(const RgbImage& image, const std::string& path, double exposure = 0);

// Linear image to a float EXR (planes R, G, B), for comparisons with other renderers.
void WriteRgbExr(const RgbImage& image, const std::string& path);

// The map's per-pixel diagnostics as a grey PNG: `plane` in valid, observations, condition
// (log10), residual, departure; scaled to its own range. "group": a colour per group, black for
// pixels solved alone.
void WriteDiagnosticPng(const SvbrdfMap& map, const std::string& plane, const std::string& path);

// Whether any pixel's normal was estimated or refused (normal_status not 0).
bool HasEstimatedNormals(const SvbrdfMap& map);

// The map's normals as a PNG in the usual normal-map colour convention, (n + 1) / 2, linear.
void WriteNormalPng(const SvbrdfMap& map, const std::string& path);

// The height integrated from the map's normals (height_from_normals.h) as a grey PNG, lowest
// black, highest white.
void WriteHeightPng(const SvbrdfMap& map, const std::string& path);

// Each estimated normal's uncertainty (normal_uncertainty_deg) in viridis on a log scale, black
// where none was estimated.
void WriteNormalUncertaintyPng(const SvbrdfMap& map, const std::string& path);

// The quick looks of a map into `dir` as `prefix`NAME.png: the BRDF at a diffuse-looking and at
// a mirror configuration (diffuse, specular), and the diagnostics (valid, observations,
// condition, residual; group and departure for a pooled map; normal, height and
// normal_uncertainty where normals were estimated). Returns the NAMEs written.
std::vector<std::string> WriteQuickLooks(const SvbrdfMap& map, const BasisView& basis,
                                         const std::string& dir, const std::string& prefix);

}  // namespace acq
