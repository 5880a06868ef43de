#include "acq/reconstruction_job.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "brdf/pooled_solver.h"
#include "core/error.h"
#include "core/progress.h"
#include "core/splitmix.h"

namespace acq {
namespace {

// Whether pixel `index` is one of the model's sample: a hash of the index and the seed against
// the sampled fraction, so the sample is spread over the whole image and does not depend on
// how the source is cut into bands.
bool InSample(std::size_t index, double fraction, std::uint64_t seed) {
  const std::uint64_t z = SplitMix64Finalise(index + seed * kGoldenGamma);
  return double(z >> 11) * 0x1.0p-53 < fraction;
}

// The first pass of the pooled reconstruction: the sample's observations.
PixelObservations ReadSample(ObservationSource& source, const ReconstructionOptions& options) {
  const std::size_t pixels = std::size_t(source.Width()) * std::size_t(source.Height());
  const double fraction = double(options.pooled.sample_pixels) / double(pixels);
  std::vector<std::size_t> indices;
  for (std::size_t i = 0; i < pixels; ++i)
    if (InSample(i, fraction, options.pooled.seed)) indices.push_back(i);
  if (options.progress)
    std::fprintf(stderr, "reconstruct: reading %zu sample pixels\n", indices.size());
  return source.Pixels(indices, options.band_rows);
}

// The pooled solve of pixels `which` as read (at the sample's normal), in that order.
PixelSolution SolveAsRead(const BasisView& basis, const PixelObservations& as_read,
                          const PooledModel& model, const PixelSolveOptions& solve,
                          const std::vector<int>& which, int components) {
  const PixelObservations gathered = as_read.Gather(which);
  PixelSolution solution;
  solution.Resize(gathered.pixels, components);
  SolvePixelsPooled(basis, gathered, model, solve, &solution);
  return solution;
}

// Pixels `back` go back to the sample's normal (kAssumed) and are solved again as read, as the
// pooled solve chooses; counted in `taken_back` (the report's count for the reason).
void TakeBackNormals(const BasisView& basis, const PixelObservations& as_read,
                     const PooledModel& model, const PixelSolveOptions& solve,
                     const std::vector<int>& back, PixelNormals* normals, PixelSolution* solution,
                     long* taken_back) {
  *taken_back += long(back.size());
  if (back.empty()) return;
  solution->Scatter(SolveAsRead(basis, as_read, model, solve, back, solution->components), back);
  for (int p : back) {
    normals->normal[std::size_t(p)] = Eigen::Vector3f::UnitZ();
    normals->status[std::size_t(p)] = NormalStatus::kAssumed;
    normals->uncertainty_deg[std::size_t(p)] = kNoNormalUncertainty;
  }
}

// A pixel whose normal was estimated but which the pooled solve left alone (no group of the
// map's model explains it, or its left-out views preferred its own solve to its group's prior):
// alone in a tilted frame its coefficients extrapolate wildly (the embossed card through acqd:
// 20 such pixels held 99% of a validation view's squared error; docs/reconstruction.md,
// "Normals"). Its normal was judged by a material's centre, so it is solved again as that
// judgement assumes, with the prior of the group whose centre explains it, at its estimated
// normal and at the sample's: the normal stays where a group explains it tilted and fits it
// better tilted than flat. Otherwise it is taken back (TakeBackNormals). Counts both in `report`.
void SettleUnexplainedNormals(const BasisView& basis, const PixelObservations& as_read,
                              const PixelObservations& turned, const PooledModel& model,
                              const PixelSolveOptions& solve, PixelNormals* normals,
                              PixelSolution* solution, ReconstructionReport* report) {
  std::vector<int> alone;
  for (int p = 0; p < as_read.pixels; ++p)
    if (normals->status[p] == NormalStatus::kEstimated && solution->group[p] < 0)
      alone.push_back(p);
  if (alone.empty()) return;
  const auto solve_with_prior = [&](const PixelObservations& from) {
    const PixelObservations gathered = from.Gather(alone);
    PixelSolution s;
    s.Resize(gathered.pixels, solution->components);
    SolvePixelsPooled(basis, gathered, model, solve, &s, 0, PriorChoice::kWhereExplained);
    return s;
  };
  const PixelSolution tilted = solve_with_prior(turned), flat = solve_with_prior(as_read);
  solution->Scatter(tilted, alone);
  std::vector<int> back;
  for (std::size_t i = 0; i < alone.size(); ++i)
    if (tilted.group[i] < 0 || (flat.group[i] >= 0 && !(tilted.residual[i] < flat.residual[i])))
      back.push_back(alone[i]);
  report->normals_settled += long(alone.size() - back.size());
  TakeBackNormals(basis, as_read, model, solve, back, normals, solution, &report->normals_reverted);
}

// NormalSearchOptions::confirmation kRegrouped or kAll: an estimated normal whose pixel the
// pooled solve put in a group (in another group than it puts the pixel flat, for kRegrouped)
// stays only where that solve fits the pixel better tilted than flat; otherwise it is taken
// back (TakeBackNormals). The search judged the normal by the reference's centres; a pixel of
// one material that another material's lobe, turned where no view looked, explains as well
// tilted, is then solved as that material with a highlight no view of the plan saw
// (docs/reconstruction.md, "The map's own solve confirms a tilt").
void ConfirmGroupedNormals(const BasisView& basis, const PixelObservations& as_read,
                           const PooledModel& model, const PixelSolveOptions& solve,
                           NormalConfirmation confirmation, PixelNormals* normals,
                           PixelSolution* solution, ReconstructionReport* report) {
  if (confirmation == NormalConfirmation::kAlone) return;
  std::vector<int> grouped;
  for (int p = 0; p < as_read.pixels; ++p)
    if (normals->status[p] == NormalStatus::kEstimated && solution->group[p] >= 0)
      grouped.push_back(p);
  if (grouped.empty()) return;
  const PixelSolution flat =
      SolveAsRead(basis, as_read, model, solve, grouped, solution->components);
  std::vector<int> back;
  for (std::size_t i = 0; i < grouped.size(); ++i) {
    const int p = grouped[i];
    const bool judged =
        confirmation == NormalConfirmation::kAll || flat.group[i] != solution->group[p];
    if (judged && !(solution->residual[p] < flat.residual[i])) back.push_back(p);
  }
  TakeBackNormals(basis, as_read, model, solve, back, normals, solution, &report->normals_reverted);
}

// NormalSearchOptions::mixed_same_group: a normal the search judged by two centres mixed, whose
// pixel the map's solve puts in another group tilted than flat (a group flat), is taken back
// (TakeBackNormals).
void ConfirmMixedNormals(const BasisView& basis, const PixelObservations& as_read,
                         const PooledModel& model, const PixelSolveOptions& solve,
                         PixelNormals* normals, PixelSolution* solution,
                         ReconstructionReport* report) {
  std::vector<int> mixed;
  for (int p = 0; p < as_read.pixels; ++p)
    if (normals->status[p] == NormalStatus::kEstimated && normals->mixed[p] &&
        solution->group[p] >= 0)
      mixed.push_back(p);
  if (mixed.empty()) return;
  const PixelSolution flat = SolveAsRead(basis, as_read, model, solve, mixed, solution->components);
  std::vector<int> back;
  for (std::size_t i = 0; i < mixed.size(); ++i)
    if (flat.group[i] >= 0 && flat.group[i] != solution->group[mixed[i]]) back.push_back(mixed[i]);
  TakeBackNormals(basis, as_read, model, solve, back, normals, solution,
                  &report->normals_mixed_regrouped);
}

}  // namespace

void ReconstructionOptions::Check(const BasisView& basis) const {
  solve.Check(basis);
  pooled.Check();
  normals.Check(basis);
  if (band_rows < 1) throw UserError("--band-rows", "must be at least 1");
  // Tiles that share rows never cross a band: keep whole tiles in a band, so the result does
  // not depend on how the image is streamed.
  if (band_rows % solve.row_tile != 0)
    throw UserError("--band-rows",
                    "must be a multiple of --row-tile (" + std::to_string(solve.row_tile) + ")",
                    "e.g. --band-rows 64 with --row-tile 8");
}

void ReconstructionReport::Print() const {
  std::printf("pixels: %ld, valid %ld (%.1f%%)\n", pixels, valid,
              pixels ? 100.0 * double(valid) / double(pixels) : 0.0);
  std::printf(
      "  not valid: %ld with no usable observation, %ld with too few observations, %ld "
      "poorly conditioned\n",
      no_observation, too_few_observations, poorly_conditioned);
  if (method == ReconstructionMethod::kPooled) {
    std::printf("%s", model.Summary().c_str());
    std::printf("pooled: %ld pixels with their group's prior, %ld alone; model %.2f s\n", pooled,
                pixels - pooled, model_seconds);
  }
  if (normals_searched) std::printf("%s; %.2f s\n", NormalsSummary().c_str(), normal_seconds);
  if (ManyNormalsRefused()) std::printf("  %s\n", NormalsWarning().c_str());
  std::printf("time: %.3f s solving, %.2f s in all: %.3f megapixels/s\n", solve_seconds,
              total_seconds, total_seconds > 0 ? double(pixels) / total_seconds / 1e6 : 0.0);
}

bool ReconstructionReport::ManyNormalsRefused() const {
  return normals_searched && double(normals_refused) > kRefusedShareWarning * double(pixels);
}

std::string ReconstructionReport::NormalsSummary() const {
  char line[512];
  std::snprintf(line, sizeof line,
                "normals: %ld estimated, %ld refused, %ld without evidence for a tilt (the "
                "sample's normal kept), %ld taken back (the map's solve fits them no better "
                "tilted than flat), %ld taken back (judged as two inks mixed, in another "
                "group tilted than flat), %ld kept with their group's prior",
                normals_estimated, normals_refused, normals_no_evidence, normals_reverted,
                normals_mixed_regrouped, normals_settled);
  return line;
}

std::string ReconstructionReport::NormalsWarning() const {
  if (!ManyNormalsRefused()) return "";
  char line[512];
  std::snprintf(line, sizeof line,
                "WARNING: %.1f%% of the pixels refused a normal: relief steeper than the "
                "search's %.0f degree cone (or data that cannot tell a tilt) there: their "
                "normals are kept flat (normal_status 2) and their BRDFs solved as if flat, "
                "so use the map there with care",
                100.0 * double(normals_refused) / double(pixels), normals_max_tilt_deg);
  return line;
}

ReconstructionReport Reconstruct(const BasisView& basis, ObservationSource& source,
                                 const ReconstructionOptions& options, SvbrdfMapInfo info,
                                 const std::string& map_path) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  options.Check(basis);
  const int w = source.Width(), h = source.Height();
  ReconstructionReport report;
  report.method = options.method;
  report.normals_searched = options.normals.enabled;
  report.normals_max_tilt_deg = options.normals.max_tilt_deg;
  const bool pooled = options.method == ReconstructionMethod::kPooled;
  // Normals judged by the material groups' centres need a model fitted before any normal is
  // known (the observations taken as flat), whatever the method.
  const bool centre_normals =
      options.normals.enabled && options.normals.criterion == NormalCriterion::kCentre;
  PooledModel normals_reference;
  if (pooled || centre_normals) {
    const PixelObservations sample = ReadSample(source, options);
    if (centre_normals)
      normals_reference =
          FitNormalReference(basis, sample, options.solve, options.pooled, options.normals);
    // The model is fitted on the sample as read, its observations taken as flat: fitted on them
    // turned into their estimated normals, a few wrong ones scattered the groups until every
    // trial merged back into one (the embossed card through acqd: 1 group, black fabric 1.17
    // against 0.20; docs/reconstruction.md, "Normals").
    if (pooled) report.model = FitPooledModel(basis, sample, options.solve, options.pooled);
    report.model_seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (pooled) info.model = report.model.Summary();
  }
  const int k = pooled ? report.model.components : options.solve.components;
  info.method = ReconstructionMethodName(options.method);
  info.width = w;
  info.height = h;
  info.components = k;
  info.eta = options.solve.eta;
  info.lookup = RowLookupName(options.solve.lookup);
  info.pixel_size_mm = source.PixelSizeMm();
  info.source = source.Describe();
  SvbrdfMapWriter writer(map_path, info);
  const int planes = int(SvbrdfChannelNames(k).size());
  std::vector<std::vector<float>> band(planes);
  Progress progress("reconstruct: rows", std::size_t(h), options.progress);
  for (int y0 = 0; y0 < h; y0 += options.band_rows) {
    const int rows = std::min(options.band_rows, h - y0);
    PixelObservations obs = source.Rows(y0, rows);
    const auto normal_start = Clock::now();
    const bool settle = pooled && options.normals.enabled;
    const PixelObservations as_read = settle ? obs : PixelObservations();
    PixelNormals normals =
        EstimateNormals(basis, &obs, options.solve, options.normals, &normals_reference);
    report.normal_seconds += std::chrono::duration<double>(Clock::now() - normal_start).count();
    PixelSolution solution;
    solution.Resize(obs.pixels, k);
    const auto solve_start = Clock::now();
    if (pooled)
      SolvePixelsPooled(basis, obs, report.model, options.solve, &solution);
    else
      SolvePixels(basis, obs, options.solve, &solution);
    if (settle) {
      ConfirmGroupedNormals(basis, as_read, report.model, options.solve,
                            options.normals.confirmation, &normals, &solution, &report);
      SettleUnexplainedNormals(basis, as_read, obs, report.model, options.solve, &normals,
                               &solution, &report);
      if (options.normals.mixed_same_group)
        ConfirmMixedNormals(basis, as_read, report.model, options.solve, &normals, &solution,
                            &report);
    }
    report.solve_seconds += std::chrono::duration<double>(Clock::now() - solve_start).count();
    // Pixel-major solution -> one plane per channel for the map.
    const std::size_t n = std::size_t(obs.pixels);
    for (auto& p : band) p.resize(n);
    for (std::size_t p = 0; p < n; ++p) {
      for (int c = 0; c < 3 * k; ++c) band[c][p] = solution.coefficients[p * 3 * k + c];
      band[3 * k][p] = solution.valid[p];
      band[3 * k + 1][p] = solution.observations[p];
      band[3 * k + 2][p] = solution.condition[p];
      band[3 * k + 3][p] = solution.residual[p];
      band[3 * k + 4][p] = solution.group[p];
      band[3 * k + 5][p] = solution.departure[p];
      for (int a = 0; a < 3; ++a) band[3 * k + 6 + a][p] = normals.normal[p][a];
      band[3 * k + 9][p] = float(normals.status[p]);
      band[3 * k + 10][p] = normals.uncertainty_deg[p];
      report.normals_estimated += normals.status[p] == NormalStatus::kEstimated;
      report.normals_refused += normals.status[p] == NormalStatus::kRefused;
      report.normals_no_evidence += normals.status[p] == NormalStatus::kNoEvidence;
      report.pooled += solution.group[p] >= 0;
      ++report.pixels;
      if (solution.valid[p]) {
        ++report.valid;
      } else if (solution.observations[p] == 0) {
        ++report.no_observation;
      } else if (solution.observations[p] < options.solve.MinObservations()) {
        ++report.too_few_observations;
      } else {
        ++report.poorly_conditioned;
      }
    }
    std::vector<const float*> pointers;
    for (const auto& p : band) pointers.push_back(p.data());
    writer.WriteRows(rows, pointers);
    progress.Tick(std::size_t(rows));
  }
  writer.Finish();
  report.total_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

}  // namespace acq
