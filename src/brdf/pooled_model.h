// The pooled reconstruction's model (docs/reconstruction.md, "Pooled"): a sample's pixels grouped
// by material, each group's centre BRDF fitted from all its pixels' observations, and the
// strength of the prior that pulls a pixel towards its centre. Every size of the model is chosen
// from the data by held-out views, on a sample of the image's pixels held in memory:
//   - the number of groups G: k-means on the pixels' independent solutions (a space the near
//     field does not shift: each pixel's coefficients, not its observations), then each pixel's
//     leave-one-view-out error with its group's prior; the smallest G within 0.1% of the best
//     (a larger model must earn its keep: "model no more than a scene needs"); and no groups at
//     all unless the model beats every pixel alone by 1%;
//   - each group's centre from its pixels weighted by how near their directions are to the
//     plan's (design_sigma_deg): the directions were optimised for the whole grid's error; then
//     again from the 90% of them that centre explains best (mixed pixels and strays left out),
//     unless the held-out views say the centre from every member was clearly better;
//   - each group's centre components k_c (up to the basis's stored ones): one view left out of
//     all the group's pixels at once, the centre fitted from the rest, its error on that view;
//   - each group's prior strength lambda: each pixel's exact leave-one-view-out error of the
//     ridge towards the centre its solve uses, fitted from every view (hat-matrix formula, no
//     refits), summed over the group: whether the pixels depart from their group where the
//     group has looked (G, above, is judged with the view left out of the centre too).
// The per-pixel solve that uses the model is pooled_solver.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "brdf/basis.h"
#include "brdf/pixel_solver.h"

namespace acq {

enum class ReconstructionMethod {
  kIndependent,  // every pixel alone, from its own views (Yu et al. Sec. 3.1)
  kPooled,       // every pixel with a prior towards its material group's centre
};
// The default of plans and of `acq reconstruct`: pooled, which measured better than independent
// through acqd on the simulated card at 4 degrees (docs/reconstruction.md, "Pooled").
inline constexpr ReconstructionMethod kDefaultReconstructionMethod = ReconstructionMethod::kPooled;
// "independent", "pooled"; nullopt for another name.
const char* ReconstructionMethodName(ReconstructionMethod method);
std::optional<ReconstructionMethod> ParseReconstructionMethod(const std::string& name);

inline constexpr double kDefaultDesignSigmaDeg = 0.15;
inline constexpr double kMaxDesignSigmaDeg = 90;
// Throws UserError at `where` (a flag or a plan key) unless 0 <= deg <= kMaxDesignSigmaDeg.
void CheckDesignSigma(double deg, const std::string& where);

struct PooledOptions {
  int groups = 0;            // 0: chosen by held-out views; > 0: forced
  int max_groups = 64;       // the largest G tried
  int sample_pixels = 8192;  // pixels the model is fitted on (spread over the image)
  std::uint64_t seed = 1;    // k-means++ seeding and the sample's choice
  // Each group's centre weights its pixels by exp(-d^2 / 2 sigma^2), d the RMS angle by which a
  // pixel's light and camera directions lie farther from the sample's mean ones (at its centre:
  // the plan's) than the group's nearest pixel's. 0: every pixel alike. The default measured
  // best or near it over the card at 4 and 10 degrees, 0-10% noise, the blend, marbled and text
  // samples and 50 inks (docs/reconstruction.md, "Pooled").
  double design_sigma_deg = kDefaultDesignSigmaDeg;
  // Empty: each centre is regularised with the solve's eta, as one pixel is (what the pooled
  // solve's prior needs). Otherwise each group's centre ridge is chosen from eta times these
  // fractions by the centre's held-out views, as its components are: the normal search's
  // reference (normal_search.h), which must predict the material at directions no view saw.
  std::vector<double> centre_eta_fractions;
  // Whether the merge of k-means groups (group_merge.h) takes the field's drift out and joins
  // groups that meet without a step. Off: pieces whose means lie within kMergeSeparation
  // scatters are joined, drift and all (the rule before the field was used): the normal search's
  // reference (normal_search.h).
  bool merge_in_field = true;
  // Whether each centre leaves out the observations whose colour departs from their neighbours'
  // at the same view (colour_outliers.h: fringes at ink edges). Off: the normal search's
  // reference, whose observations are taken as flat, so that a tilted pixel's colour (a glossy
  // ink's highlight caught or missed) is data to judge normals by, not a fringe.
  bool leave_out_colour_fringes = true;
  // Whether a model whose held-out views gain less than 1% over every pixel alone is dropped
  // (no groups: the pooled solve is then the independent one). Off: the normal search's
  // reference, whose centres judge the normals whatever the pooled solve does with them.
  bool groups_must_beat_independent = true;
  void Check() const;  // throws UserError
};

struct PooledGroup {
  std::vector<double> feature;  // the k-means centroid, PooledModel::features per channel x 3
  std::vector<float> centre;    // 3 x PooledModel::components, R then G then B; zero past k_c
  int centre_components = 0;    // k_c
  double centre_eta = 0;        // the ridge the centre was fitted with
  double strength = 0;          // lambda of the prior; infinite: the pixel is its centre
  int sample_pixels = 0;
  // The sample pixels the centre was fitted from: those it explains best, or every member
  // (pooled_model.cpp, FitGroup).
  int centre_members = 0;
  double effective_pixels = 0;  // the sample pixels the centre's weights amount to
  // Its sample pixels' observations the centre left out, their colour departing from their
  // neighbours' at the same view (colour_outliers.h: fringes at ink edges).
  int colour_outliers = 0;
  double held_out_rms = 0;  // the group's pixels' leave-one-view-out RMS (log space)
  // A pixel whose observations the centre misses by more than this (RMS, log space) is not of
  // the group: the 99th percentile over the group's sample pixels.
  double misfit_limit = 0;
  // Per view (the pixels' view index): the weight of its squared misfit in the normal search's
  // score (normal_search.h, NormalSearchOptions::view_weights); empty: every view 1. Set by
  // FitNormalReference only.
  std::vector<double> view_weight;
};

struct PooledModel {
  int components = 0;           // coefficients per channel of a centre (the map's k)
  int features = 0;             // feature components per channel
  double design_sigma_deg = 0;  // PooledOptions::design_sigma_deg the centres were fitted with
  std::vector<double> weight;   // per component: the RMS log-space size of a unit coefficient
  std::vector<PooledGroup> groups;
  struct Trial {
    int groups = 0;
    double held_out_rms = 0;
  };
  std::vector<Trial> selection;         // each G tried, in order
  double held_out_rms = 0;              // the chosen model's, over the sample
  double independent_held_out_rms = 0;  // the independent solve's on the same sample
  // The held-out RMS of the groups found, when they were dropped for not beating every pixel
  // alone (PooledOptions::groups_must_beat_independent); 0 otherwise.
  double dropped_held_out_rms = 0;
  int sample_pixels = 0;  // usable pixels of the sample
  // FitNormalReference: the groups that are another group's relief were taken out, so each
  // group is a material (NormalSearchOptions::same_centre relies on it); not with a forced
  // number of groups.
  bool groups_are_materials = false;
  // A feature vector of per-channel coefficients (3 x k, R then G then B).
  void Feature(const float* coefficients, int k, double* feature) const;
  // The (at most) m groups whose centroids are nearest a feature vector, nearest first.
  std::vector<int> NearestGroups(const std::vector<double>& feature, int m) const;

  // The RMS log-space difference over the grid between two coefficient sets (3 x a, 3 x b).
  double Distance(const float* a, int ka, const float* b, int kb) const;
  std::string Summary() const;  // a few lines for the log, the map's header and the report
};

// Fits the model to the sample's pixels (any subset of the image; each pixel's own views).
// A sample too small to group (fewer than 16 usable pixels) gives a model with no groups,
// with which the pooled solve is the independent one.
PooledModel FitPooledModel(const BasisView& basis, const PixelObservations& sample,
                           const PixelSolveOptions& solve, const PooledOptions& options);

}  // namespace acq
