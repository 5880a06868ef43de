// The reconstruction job: streams an observation source band by band through the per-pixel
// solver into an SVBRDF map, so memory stays bounded by the band, not the image, and reports
// what it found (docs/architecture.md data flow: "per-pixel reconstruction -> SVBRDF maps").
#pragma once

#include <string>

#include "brdf/normal_search.h"
#include "brdf/pixel_solver.h"
#include "brdf/pooled_model.h"
#include "io/svbrdf_map.h"

namespace acq {

struct ReconstructionOptions {
  ReconstructionMethod method = kDefaultReconstructionMethod;
  PixelSolveOptions solve;
  PooledOptions pooled;         // with method kPooled
  NormalSearchOptions normals;  // enabled: each pixel's normal estimated before its solve
  int band_rows = 64;           // rows solved and written at a time
  bool progress = true;
  void Check(const BasisView& basis) const;
};

struct ReconstructionReport {
  long pixels = 0, valid = 0;
  long no_observation = 0;        // no usable view at all
  long too_few_observations = 0;  // fewer than PixelSolveOptions::MinObservations()
  long poorly_conditioned = 0;    // enough views, condition number over the limit
  // A session's: observations dropped where the Spectralon did not read its board at the point
  // (CorrespondenceSource::OffBoardObservations); set by the session's processing.
  long off_spectralon_observations = 0;
  ReconstructionMethod method = ReconstructionMethod::kIndependent;
  PooledModel model;         // kPooled: the groups and model sizes chosen
  long pooled = 0;           // kPooled: pixels solved with their group's prior (the rest alone)
  double model_seconds = 0;  // kPooled: reading the sample and fitting the model
  bool normals_searched = false;                    // options.normals.enabled
  double normals_max_tilt_deg = 0;                  // options.normals.max_tilt_deg
  long normals_estimated = 0, normals_refused = 0;  // normals.enabled
  long normals_no_evidence = 0;  // a tilt found that did not earn its keep (NormalStatus)
  // kPooled: estimated, but the map's solve fits them no better tilted than flat (or no group
  // explains them; NormalSearchOptions::confirmation): kAssumed.
  long normals_reverted = 0;
  // kPooled: estimated, left alone by the pooled solve, and kept with their group's prior (a
  // group explains them better tilted than flat; SettleUnexplainedNormals).
  long normals_settled = 0;
  // kPooled, NormalSearchOptions::mixed_same_group: estimated by two centres mixed, but the
  // map's solve puts the pixel in another group tilted than flat: kAssumed (not in
  // normals_reverted).
  long normals_mixed_regrouped = 0;
  double normal_seconds = 0;
  double solve_seconds = 0, total_seconds = 0;
  void Print() const;
  // More than kRefusedShareWarning of the pixels refused a normal: relief steeper than the
  // search's cone, or data that cannot tell, over a part of the sample worth a warning.
  bool ManyNormalsRefused() const;
  // normals_searched: "normals: ... estimated, ... refused, ..." (no newline).
  std::string NormalsSummary() const;
  // Where ManyNormalsRefused: "WARNING: ..." (no newline), what it means for the map; else "".
  std::string NormalsWarning() const;
};
// The embossed card at 10 degrees (inside the cone) refuses 1.8-2.0% of its pixels through acqd
// (ink edges where the data cannot tell); the same card at 40 degrees 7.8%.
inline constexpr double kRefusedShareWarning = 0.05;

// With method kPooled the source is read twice: once for a sample of pixels the model is fitted
// on, once for the solve (memory stays bounded by a band and the sample).
// `map_info` supplies the descriptive fields (basis path and checksum, camera model); the
// dimensions, settings and pixel size are filled in from the source and options.
ReconstructionReport Reconstruct(const BasisView& basis, ObservationSource& source,
                                 const ReconstructionOptions& options, SvbrdfMapInfo map_info,
                                 const std::string& map_path);

}  // namespace acq
