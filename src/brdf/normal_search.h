// Per-pixel shading normals recovered with the BRDF (issue 19; docs/reconstruction.md,
// "Normals"). For each pixel a candidate normal re-expresses its observations in that facet's
// frame (core/facet_frame.h: directions turned, values rescaled by n.l / l.z); a ridge solve of
// `components` coefficients gives the misfit there, and the normal minimises
//   residual(n) + prior * tan^2(tilt(n)),
// the prior keeping it near the sample's normal where the data say little. The search is
// coarse-to-fine on the slope (tan(tilt) cos(azimuth), tan(tilt) sin(azimuth)): a coarse grid
// over the cone of `max_tilt_deg` (3 x 3 by default), then 3 x 3 refinements each halving the
// step (NormalSearchMethod). Each level scores every pixel's candidates in one batch (by the
// per-pixel solver, or by the material groups' centres). The chosen normal's observations
// replace the pixel's, so any reconstruction (independent or pooled) then solves in the
// facet's frame.
#pragma once

#include <cstdint>
#include <vector>

#include <optional>
#include <string>

#include "brdf/pixel_solver.h"
#include "brdf/pooled_model.h"

namespace acq {

enum class NormalStatus : std::uint8_t {
  kAssumed = 0,     // not estimated: the sample's normal (search off, or no usable view)
  kEstimated = 1,   // the search's minimum, inside its cone
  kRefused = 2,     // the minimum lay on the cone's edge, or a view its facet faces was seen
                    // dark (relief too steep for the search, or the data cannot tell), or its
                    // uncertainty exceeded NormalSearchOptions::max_uncertainty_deg: the
                    // sample's normal kept, flagged
  kNoEvidence = 3,  // the best tilt did not lower the misfit enough to pay for its two
                    // parameters (NormalSearchOptions::evidence), or lay under
                    // NormalSearchOptions::min_tilt_deg, or was judged by another material's
                    // centre than the sample's normal (NormalSearchOptions::same_centre): the
                    // sample's normal kept
};

// What a candidate normal is scored by (the residual of its k-component solve).
enum class NormalCriterion {
  kFit,      // the misfit at the pixel's own views: lowest at a slightly wrong normal that lets
             // the coefficients bend to the data (docs/reconstruction.md, "Normals")
  kHeldOut,  // each view predicted by the solve without it (ResidualKind::kLeaveOneViewOut)
  // The misfit of the pixel's material group's centre (pooled_model.h), coefficients held: a
  // candidate normal cannot bend them, so the normal must place the lobe where the material,
  // known from all its pixels, has it. The group: of the 3 nearest to the pixel's flat solve,
  // the one whose centre fits best at the candidate, or two of them mixed
  // (NormalSearchOptions::mixed_pixels). A pixel no centre explains (misfit above the group's
  // limit at its best normal) keeps the sample's normal (kAssumed).
  kCentre,
};
const char* NormalCriterionName(NormalCriterion criterion);  // "fit", "held-out", "centre"
std::optional<NormalCriterion> ParseNormalCriterion(const std::string& name);

// Which estimated normals the map's own pooled solve must confirm, by fitting the pixel better
// tilted than at the sample's normal (the reconstruction job does it; a normal it does not
// confirm goes back to the sample's, kAssumed). The search judges a normal by a centre of the
// reference's groups; the map is solved with its own model's groups and the pixel's own
// coefficients, which may explain it otherwise.
enum class NormalConfirmation {
  kAlone,      // those the pooled solve left alone (no group of the map's explains them)
  kRegrouped,  // also those the map's solve puts in another group tilted than flat
  kAll,        // every estimated normal
};
const char* NormalConfirmationName(NormalConfirmation c);  // "alone", "regrouped", "all"
std::optional<NormalConfirmation> ParseNormalConfirmation(const std::string& name);

enum class NormalSearchMethod { kGrid, kQuadratic };
const char* NormalSearchMethodName(NormalSearchMethod method);  // "grid", "quadratic"
std::optional<NormalSearchMethod> ParseNormalSearchMethod(const std::string& name);

// 0.5: through acqd a dark fabric on a flat card took 9-12 degrees of false tilt at 0.05 (median
// 3.3 at 0.5), before the evidence test (NormalSearchOptions::evidence); offline the figures move
// by hundredths. Lower priors trade normals over the relief for validation views
// (docs/reconstruction.md, "Normals").
inline constexpr double kDefaultNormalsPrior = 0.5;
inline constexpr bool kDefaultNormalsMixedPixels = true;  // NormalSearchOptions::mixed_pixels
inline constexpr int kDefaultNormalsTrimmedViews = 1;     // NormalSearchOptions::trimmed_views
inline constexpr int kMaxNormalsTrimmedViews = 4;
inline constexpr double kDefaultNormalsMaxUncertaintyDeg = 0;  // no limit
inline constexpr double kDefaultNormalsEvidence = 1;           // NormalSearchOptions::evidence
inline constexpr double kDefaultNormalsScoreMinCos = 0;        // NormalSearchOptions::score_min_cos
// Through acqd on eight captures (docs/reconstruction.md, "Tilts the geometry's error can make"):
// both took the validation views' median errors from worse than with the search off on 19 of 24
// views to none, and the relief's normals from 1.02-1.73 to 0.86-1.48 degrees.
inline constexpr bool kDefaultNormalsViewWeights = true;   // NormalSearchOptions::view_weights
inline constexpr double kDefaultNormalsMinTiltDeg = 0.75;  // NormalSearchOptions::min_tilt_deg
inline constexpr NormalConfirmation kDefaultNormalsConfirmation = NormalConfirmation::kAlone;
// Through acqd on eleven captures (docs/reconstruction.md, "A mixed pixel's tilt keeps its
// group"): the validation views worse by relative RMS than with the search off from 12 of 33
// to 8, the relief's normals from 0.86-1.48 to 0.87-1.51 degrees. NormalSearchOptions::
// mixed_same_group.
inline constexpr bool kDefaultNormalsMixedSameGroup = true;
// The same eleven captures with mixed_same_group (docs/reconstruction.md, "A tilt keeps the
// centre that judges the pixel flat"): the views worse from 8 of 33 to 2, the relief's normals
// from 0.87-1.51 to 0.88-1.55 degrees.
inline constexpr bool kDefaultNormalsSameCentre = true;  // NormalSearchOptions::same_centre

struct NormalSearchOptions {
  bool enabled = false;
  double max_tilt_deg = 25;  // the cone searched around the sample's normal
  int components = 8;        // k of the search's solves (fewer than the views: identifiable)
  NormalCriterion criterion = NormalCriterion::kCentre;  // docs/reconstruction.md, "Normals"
  double eta = kDefaultEta;
  // Weight of tan^2(tilt) against the RMS log-space misfit (docs/reconstruction.md, "Normals",
  // for the measured trade between the normals and the validation views).
  double prior = kDefaultNormalsPrior;
  // How the coarse grid's best is refined: 3 x 3 grids, each halving the step, `levels` times
  // (kGrid), or fewer such levels and then a Newton step on the quadratic fitted to the last
  // 3 x 3 (kQuadratic). docs/reconstruction.md, "Normals", measures both.
  NormalSearchMethod method = NormalSearchMethod::kGrid;
  int levels = 0;  // refinements after the coarse grid; 0: the method's default
  // The coarse grid: (2 reach + 1)^2 slopes spaced half the cone. 1 (3 x 3, reaching the cone by
  // the refinements) found the same normals as 2 (5 x 5) in every case of the study, 13% sooner.
  int coarse_reach = 1;
  int Levels() const { return levels > 0 ? levels : method == NormalSearchMethod::kGrid ? 6 : 3; }
  // A view or light at or below this cosine to a candidate facet is not used. 0: only those
  // behind it; anything more drops the grazing views the flat solve uses (the seed paper's set
  // has lights at 85 degrees), which alone raised a flat brass card's error from 0.285 to 0.335.
  double min_cos = 0;
  // Views and lights at or below this cosine to a candidate facet are left out of its score
  // (not out of the solve that follows): at grazing incidence a degree of tilt rescales the
  // value by n.l / l.z by 20% (85 degrees), which lets a wrong normal absorb the basis's misfit
  // there; the normal shows in where the lobe falls, which the other views see.
  double score_min_cos = kDefaultNormalsScoreMinCos;
  // Views and lights at or below this cosine to an estimated facet are left out of the solve
  // that follows: a value rescaled by n.l / l.z moves by tan(theta) per radian of the normal's
  // error (6.5% a degree at 75 degrees, 20% at 85). 0: every view kept, as for a flat pixel.
  // Measured (docs/reconstruction.md, "Normals"): 0.26 helps a dark fabric and a white paint and
  // the embossed card, hurts brass and pink jasper on flat areas; hence 0.
  double estimated_min_cos = 0;
  // A tilt must earn its two parameters: with N = 3 x views residuals, the best candidate is
  // taken only if N ln(misfit^2 at the sample's normal / misfit^2 at it) > evidence x 2 ln N
  // (evidence 1: the Bayesian information criterion; 0: any lower score wins). Without it the
  // search tilts flat pixels of materials whose misfit hardly depends on the normal (a dark
  // fabric), whose solve then moves far: a degree of tilt rescales a grazing view's value by
  // 20%.
  double evidence = kDefaultNormalsEvidence;
  // Criterion kCentre: a pixel may also be explained by two of its groups' centres mixed (BRDFs
  // mixed linearly, shares 1/4, 1/2, 3/4), at every candidate normal and the sample's: a pixel
  // at an ink edge is then judged by the mixture, not by one ink whose lobe a tilt moves.
  // Measured (docs/reconstruction.md, "Mixed pixels"): through acqd it takes the validation
  // views' wild renders away and improves the normals over the relief; hence on.
  bool mixed_pixels = kDefaultNormalsMixedPixels;
  // Criterion kCentre: the misfit a candidate is scored by leaves out the pixel's `trimmed_views`
  // worst-explained views (least trimmed squares). A pixel on a relief's edge straddles facets,
  // and in a view or two its footprint holds another facet's highlight that no single normal
  // explains; untrimmed, that view drags the normal off or onto the cone's edge (refused).
  // Measured through acqd (docs/reconstruction.md, "One view left out of the score"): 1 took
  // the relief's normals from 1.90-2.00 to 1.57-1.83 degrees on six captures; hence 1 (offline,
  // where no footprint straddles facets, it costs up to 0.19 degree). The group's misfit limit
  // (PooledGroup::misfit_limit, over every view) is then a little more lenient than it was.
  int trimmed_views = kDefaultNormalsTrimmedViews;
  // An estimated normal whose uncertainty (PixelNormals::uncertainty_deg) exceeds this many
  // degrees is refused (the sample's normal kept, flagged); 0: no limit. A mirror-like ink's
  // normal that no view's highlight pins lands in the gaps between the plan's half vectors,
  // where a view the plan lacks then sees a highlight the sample does not have. Measured
  // (docs/reconstruction.md, "How well the data fix a normal"): a limit trades the relief's
  // normals for such views; hence none by default.
  double max_uncertainty_deg = kDefaultNormalsMaxUncertaintyDeg;
  // Pooled reconstructions: which estimated normals the map's solve must confirm
  // (NormalConfirmation; docs/reconstruction.md, "The map's own solve confirms a tilt").
  NormalConfirmation confirmation = kDefaultNormalsConfirmation;
  // Criterion kCentre: each view's squared misfit weighted by how well the group's centre
  // predicts its own pixels there (FitNormalReference; PooledGroup::view_weight): the views
  // near a sharp peak, where a few tenths of a degree of the calibrated directions move the
  // value by tens of percent, weigh least. Normalised so that a typical member's misfit is
  // unchanged: the prior, the evidence test and the group's misfit limit keep their scale.
  bool view_weights = kDefaultNormalsViewWeights;
  // A best tilt under this many degrees is not told from the error of the directions the
  // calibration gives (a tilt turns a pixel's directions as that error does): the sample's
  // normal kept (kNoEvidence). docs/reconstruction.md, "Tilts the geometry's error can make".
  double min_tilt_deg = kDefaultNormalsMinTiltDeg;
  // Pooled reconstructions: a normal the search judged by two centres mixed (mixed_pixels) stays
  // only where the map's solve puts its pixel in the same group tilted as flat (when it puts it
  // in one flat); otherwise it goes back to the sample's normal. The map solves a pixel as one
  // group's material: turned into the facet's frame, a pixel at an ink edge can fit a glossy
  // ink's prior whose lobe falls between the plan's views, and is then rendered with that ink's
  // whole highlight where the search judged it by a share of it (black fabric on an embossed
  // border given brass's: 80% of a validation view's squared error from three pixels).
  bool mixed_same_group = kDefaultNormalsMixedSameGroup;
  // Criterion kCentre: a best normal judged by one centre other than the one that judges the
  // pixel at the sample's normal keeps the sample's normal (kNoEvidence). The reference's groups
  // are materials (FitNormalReference), and a tilt does not change a pixel's material: a pixel
  // on a ridge at an ink's edge, its footprint straddling facets and inks, is explained flat by
  // one ink and tilted by a glossier one, whose highlight the map then puts where only views the
  // plan lacks look (brass on a ridge at white paint's edge: docs/reconstruction.md). Only with
  // a reference whose groups are materials (PooledModel::groups_are_materials): with a forced
  // number of groups one may be a relief, and a relief pixel is then judged flat by it.
  bool same_centre = kDefaultNormalsSameCentre;
  int chunk_pixels = 2048;  // pixels per batch of candidates (memory: chunk x 25 x views)
  void Check(const BasisView& basis) const;  // throws UserError
};

// A normal's uncertainty where none was estimated (PixelNormals::uncertainty_deg).
inline constexpr float kNoNormalUncertainty = -1;

struct PixelNormals {
  std::vector<Eigen::Vector3f> normal;  // per pixel, sample frame, unit
  std::vector<NormalStatus> status;
  // How far from the estimate (degrees) lie normals the pixel's data cannot tell from it: the
  // largest step of the search at which a candidate that far scored within the 95% region of
  // two parameters (profile likelihood of the RMS misfit over its 3 x views residuals); 0 when
  // even the finest step's candidates lie outside. kNoNormalUncertainty where no normal was
  // estimated, but set for a normal refused for it (NormalSearchOptions::max_uncertainty_deg).
  std::vector<float> uncertainty_deg;
  // 1 where the estimated normal was judged by two centres mixed (NormalSearchOptions::
  // mixed_pixels); 0 elsewhere.
  std::vector<std::uint8_t> mixed;
  void Resize(int pixels);  // flat, kAssumed, kNoNormalUncertainty, not mixed
};

// What criterion kCentre judges a normal by: the material groups (pooled_model.h) fitted on a
// sample of the image's pixels taken as flat, each centre's ridge chosen by its held-out views
// from eta x 1, 1/4, ..., 1/256 (PooledOptions::centre_eta_fractions). A centre regularised as
// one pixel is (eta) leaves a residual at grazing views that a tilt of 1-2 degrees absorbs (a
// dark fabric at 4 degrees: 1 degree of false tilt, its map 0.85 against 0.50 flat); one
// barely regularised extrapolates wildly to the directions a tilted candidate asks about. Its
// centres weigh every pixel alike (PooledOptions::design_sigma_deg 0). The groups must be
// materials: the number of groups is searched past merges, as for the map's model, and then
// each group whose pixels a larger group's centre explains better tilted (by `search`) than its
// own centre does flat is that group's relief and is taken out (unless the number of groups is
// forced, or the search is off).
PooledModel FitNormalReference(const BasisView& basis, const PixelObservations& sample,
                               const PixelSolveOptions& solve, const PooledOptions& pooled,
                               const NormalSearchOptions& search);

// Chooses every pixel's normal and rewrites `observations` into its facet's frame (pixels
// refused, assumed or without evidence keep theirs), each candidate scored by
// options.criterion. `solve` supplies the lookup and the minimum of views.
// NormalCriterion::kCentre needs a reference with groups; without one such a search leaves
// every normal assumed.
PixelNormals EstimateNormals(const BasisView& basis, PixelObservations* observations,
                             const PixelSolveOptions& solve, const NormalSearchOptions& options,
                             const PooledModel* reference = nullptr);

// One pixel's observations turned into the frame of normal n (what the search tries and what it
// applies): values rescaled by n.l / l.z, views grazing the facet (cos below min_cos) missing.
void ToFacetFrame(const Eigen::Vector3f& n, double min_cos, const PixelObservations& from,
                  int pixel, PixelObservations* to, int to_pixel);

}  // namespace acq
