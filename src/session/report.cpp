#include "session/report.h"

#include "brdf/evaluation.h"

#include <cstdio>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/session_catalog.h"

namespace acq {
namespace {

// A validation view's worst pixel is named in report.txt when it carries this share of the
// view's squared error or more (report.json has it always).
constexpr double kWorstPixelShareShown = 0.1;

std::string Share(double part, double whole) {
  char s[32];
  std::snprintf(s, sizeof s, "%5.1f%%", whole > 0 ? 100 * part / whole : 0.0);
  return s;
}

}  // namespace

double SessionReport::OverheadS() const {
  const ProcessReport& p = process;
  return wall_s - capture.motion_s - capture.exposure_s - capture.transfer_s - capture.settings_s -
         capture.bracket_probe_s - capture.operator_s - background_wait_s - p.hdr_s -
         p.calibration_s - p.correspondence_s - p.reconstruction_s - p.validation_s - scoring_s;
}

std::string SessionReport::Json() const {
  // nlohmann writes the texts escaped and NaN or infinities as null (a figure that could not
  // be computed), so the report is valid JSON whatever it holds; keys keep their order.
  using Json = nlohmann::ordered_json;
  const ProcessReport& p = process;
  const ReconstructionReport& r = p.reconstruction;
  Json j;
  j["plan"] = plan;
  j["backend"] = backend;
  j["session"] = session;
  j["captured"] = captured;
  j["time_s"] = {{"wall", wall_s},
                 {"motion", capture.motion_s},
                 {"exposure", capture.exposure_s},
                 {"transfer", capture.transfer_s},
                 {"camera_settings", capture.settings_s},
                 {"bracket_probes", capture.bracket_probe_s},
                 {"operator", capture.operator_s},
                 {"background_wait", background_wait_s},
                 {"background_busy", background_busy_s},
                 {"frame_writer_busy", writer_busy_s},
                 {"frame_writer_blocked", writer_blocked_s},
                 {"hdr_merge", p.hdr_s},
                 {"calibration", p.calibration_s},
                 {"correspondence", p.correspondence_s},
                 {"reconstruction", p.reconstruction_s},
                 {"validation", p.validation_s},
                 {"scoring", scoring_s},
                 {"planning", planning_s},
                 {"daemon_overhead", OverheadS()}};
  j["time_s"]["after_capture"] = after_capture_s;
  j["frames"] = {{"taken", capture.frames_taken},
                 {"already_there", capture.frames_skipped},
                 {"incomplete", incomplete_frames},
                 {"retaken", retaken_frames}};
  j["map"] = {{"file", "svbrdf.exr"},
              {"width", p.reference_width},
              {"height", p.reference_height},
              {"pixel_size_mm", p.pixel_size_mm},
              {"pixels", r.pixels},
              {"valid", r.valid},
              {"no_observation", r.no_observation},
              {"too_few_observations", r.too_few_observations},
              {"poorly_conditioned", r.poorly_conditioned},
              {"off_spectralon_observations", r.off_spectralon_observations},
              {"method", ReconstructionMethodName(r.method)}};
  if (r.method == ReconstructionMethod::kPooled) {
    Json groups = Json::array(), tried = Json::array();
    for (const PooledGroup& g : r.model.groups)
      groups.push_back({{"sample_pixels", g.sample_pixels},
                        {"centre_members", g.centre_members},
                        {"centre_components", g.centre_components},
                        {"colour_outliers", g.colour_outliers},
                        {"strength", g.strength},
                        {"held_out_rms", g.held_out_rms}});
    for (const PooledModel::Trial& t : r.model.selection)
      tried.push_back({{"groups", t.groups}, {"held_out_rms", t.held_out_rms}});
    j["map"]["pooled"] = {
        {"groups", groups},
        {"groups_tried", tried},
        {"held_out_rms", r.model.held_out_rms},
        {"independent_held_out_rms", r.model.independent_held_out_rms},
        // groups found but dropped: they did not beat every pixel alone
        {"dropped_groups_held_out_rms",
         r.model.dropped_held_out_rms > 0 ? Json(r.model.dropped_held_out_rms) : Json(nullptr)},
        {"sample_pixels", r.model.sample_pixels},
        {"pixels_with_prior", r.pooled},
        {"model_s", r.model_seconds}};
  }
  if (r.normals_searched)
    j["map"]["normals"] = {{"estimated", r.normals_estimated},
                           {"refused", r.normals_refused},
                           {"no_evidence", r.normals_no_evidence},
                           {"taken_back", r.normals_reverted},
                           {"mixed_regrouped", r.normals_mixed_regrouped},
                           {"kept_with_prior", r.normals_settled},
                           {"many_refused", r.ManyNormalsRefused()},
                           {"search_s", r.normal_seconds}};
  const SessionCalibration& c = p.calibration;
  int found = 0;
  for (const BoardPoseResult& b : c.boards) found += b.found;
  j["calibration"] = {{"camera", "calibration/camera.cameramodel"},
                      {"lensmodel", c.camera.lensmodel_name()},
                      {"intrinsics_from", c.intrinsics_from},
                      {"intrinsics_rms_px", c.intrinsics_rms_px},
                      {"uncertainty_centre_px", c.uncertainty_centre_px},
                      {"uncertainty_worst_px", c.uncertainty_worst_px},
                      {"board_poses", c.boards.size()},
                      {"board_poses_found", found},
                      {"views_left_out", p.views_left_out.size()},
                      {"warnings", c.warnings}};
  j["validation"] = Json::array();
  for (const ValidationSummary& v : p.validation)
    j["validation"].push_back({{"direction", v.name},
                               {"pixels", v.pixels},
                               {"relative_rms", v.relative_rms},
                               {"median_relative", v.median_relative},
                               {"median_delta_e2000", v.median_delta_e2000},
                               {"render", v.render},
                               {"worst_pixel", {v.worst_x, v.worst_y}},
                               {"worst_pixel_share", v.worst_share}});
  if (colour()) {
    std::vector<double> validation_delta_e;
    for (const ValidationSummary& v : p.validation)
      validation_delta_e.push_back(v.median_delta_e2000);
    j["colour"] = {{"camera_filter", CfaName(colour_filter)}};
    j["colour"]["delta_e2000_validation_median"] =
        validation_delta_e.empty() ? Json(nullptr) : Json(Median(validation_delta_e));
    if (p.rec709_from_camera) {
      Json rows = Json::array();
      for (int r = 0; r < 3; ++r)
        rows.push_back({(*p.rec709_from_camera)(r, 0), (*p.rec709_from_camera)(r, 1),
                        (*p.rec709_from_camera)(r, 2)});
      j["colour"]["rec709_from_camera"] = rows;
      j["colour"]["matrix_from"] = p.chart ? "chart" : "plan";
    }
    if (p.chart) {
      j["colour"]["chart_residual_delta_e2000_max"] = p.chart->max_delta_e2000;
      j["colour"]["chart_residual_delta_e2000_median"] = p.chart->median_delta_e2000;
      j["colour"]["chart_patches_used"] = p.chart->used;
      j["colour"]["chart_turned_deg"] = ChartTurnDegrees(p.chart->turned);
      Json patches = Json::array();
      for (const ChartPatchFit& patch : p.chart->patches)
        patches.push_back(patch.used
                              ? Json{{"name", patch.name}, {"delta_e2000", patch.delta_e2000}}
                              : Json{{"name", patch.name}, {"dropped", patch.dropped}});
      j["colour"]["chart_patches"] = patches;
    }
    if (scored) {
      std::vector<double> floor, map_vs_truth;
      for (const ValidationTruth& v : validation_truth) {
        floor.push_back(v.capture_delta_e2000);
        map_vs_truth.push_back(v.map_delta_e2000);
      }
      // What the capture's own noise costs (the truth against the capture), and the map
      // against the truth without it: delta_e2000_validation_median read beside these.
      j["colour"]["delta_e2000_validation_truth_vs_capture_median"] =
          floor.empty() ? Json(nullptr) : Json(Median(floor));
      j["colour"]["delta_e2000_validation_map_vs_truth_median"] =
          map_vs_truth.empty() ? Json(nullptr) : Json(Median(map_vs_truth));
      j["colour"]["delta_e2000_albedo_median"] = score.albedo_delta_e2000_median;
      j["colour"]["material_delta_e2000_albedo_median"] = score.material_albedo_delta_e2000_median;
      j["colour"]["material_delta_e2000_albedo_of_mean"] = score.material_albedo_mean_delta_e2000;
      j["colour"]["channel_median_log_rmse"] = score.channel_median_log_rmse;
    }
  }
  if (scored)
    j["ground_truth"] = {{"median_log_rmse", score.median_log_rmse},
                         {"median_log_rmse_valid", score.median_log_rmse_valid},
                         {"pixels", score.pixels},
                         {"valid", score.valid},
                         {"homogeneous_median_log_rmse", homogeneous_median_log_rmse},
                         {"alignment_median_px", alignment_median_px},
                         {"alignment_max_px", alignment_max_px},
                         {"board_eye_error_median_deg", board_eye_error_median_deg},
                         {"board_eye_error_max_deg", board_eye_error_max_deg},
                         {"material_median_log_rmse", score.material_median_log_rmse},
                         {"material_homogeneous_log_rmse", homogeneous_log_rmse}};
  if (normals) {
    const auto finite = [](double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); };
    j["normals"] = {
        {"median_error_deg_relief", finite(normals->median_error_deg_relief)},
        {"median_error_deg_relief_assumed_flat",
         finite(normals->median_error_deg_relief_assumed_flat)},
        {"median_tilt_deg_flat", finite(normals->median_tilt_deg_flat)},
        {"median_error_deg_relief_one_material",
         finite(normals->median_error_deg_relief_one_material)},
        {"median_error_deg_relief_ink_edges", finite(normals->median_error_deg_relief_ink_edges)},
        {"relief_pixels_one_material", normals->relief_pixels_one_material},
        {"relief_pixels_ink_edges", normals->relief_pixels_ink_edges},
        {"relief_pixels", normals->relief_pixels},
        {"flat_pixels", normals->flat_pixels},
        {"material_median_tilt_deg_flat",
         [&] {
           Json per = Json::array();
           for (double v : normals->material_median_tilt_deg_flat) per.push_back(finite(v));
           return per;
         }()},
        {"refused", normals->refused},
        {"no_evidence", normals->no_evidence},
        {"median_uncertainty_deg", finite(normals->median_uncertainty_deg)},
        {"median_error_deg_relief_certain", finite(normals->median_error_deg_relief_certain)},
        {"median_error_deg_relief_uncertain", finite(normals->median_error_deg_relief_uncertain)},
        {"relief_pixels_certain", normals->relief_pixels_certain},
        {"relief_pixels_uncertain", normals->relief_pixels_uncertain}};
  }
  if (scored) {
    j["ground_truth"]["validation"] = Json::array();
    for (const ValidationTruth& v : validation_truth)
      j["ground_truth"]["validation"].push_back(
          {{"direction", v.name},
           {"truth_vs_capture_relative_rms", v.capture_relative_rms},
           {"truth_vs_capture_median_delta_e2000", v.capture_delta_e2000},
           {"map_vs_truth_relative_rms", v.map_relative_rms},
           {"map_vs_truth_median_delta_e2000", v.map_delta_e2000}});
  }
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

namespace {

// Where the time went, and the frames.
std::string TimeText(const SessionReport& s) {
  const ProcessReport& p = s.process;
  std::ostringstream t;
  char line[512];
  t << "where the time went (" << s.wall_s << " s in all):\n";
  struct Row {
    const char* what;
    double s;
    bool processing;  // a stage `acq session process` runs too
  };
  const CaptureReport& c = s.capture;
  const Row rows[] = {{"motion and settling", c.motion_s, false},
                      {"exposure", c.exposure_s, false},
                      {"transfer", c.transfer_s, false},
                      {"camera settings (exposure)", c.settings_s, false},
                      {"choosing brackets (probes)", c.bracket_probe_s, false},
                      {"waiting for the operator", c.operator_s, false},
                      {"finishing the overlapped work", s.background_wait_s, false},
                      {"HDR merge (what was left)", p.hdr_s, true},
                      {"calibration (detect, solve)", p.calibration_s, true},
                      {"correspondence", p.correspondence_s, true},
                      {"reconstruction", p.reconstruction_s, true},
                      {"validation renders", p.validation_s, true},
                      {"scoring against the truth", s.scoring_s, false},
                      {"daemon overhead", s.OverheadS(), false},
                      {"  of which planning the order", s.planning_s, false}};
  // Processed again (acq session process): the capture's rows and the daemon's are not this
  // run's.
  for (const Row& row : rows) {
    if (!s.captured && !row.processing) continue;
    std::snprintf(line, sizeof line, "  %-30s %8.2f s  %s\n", row.what, row.s,
                  Share(row.s, s.wall_s).c_str());
    t << line;
  }
  if (!s.captured) return t.str() + "\nframes: as captured, none taken\n";
  std::snprintf(
      line, sizeof line,
      "  (during the capture, on a worker: %d poses merged, the calibration and the "
      "correspondence, %.2f s of its time; writing the frames, on their own, %.2f s, the capture\n"
      "  waiting %.2f s of it for room in the writer's queue)\n"
      "  (from the last frame to the processed session: %.2f s)\n"
      "\nframes: %d taken, %d already there; %ld arrived incomplete, %ld retaken\n",
      s.background_poses, s.background_busy_s, s.writer_busy_s, s.writer_blocked_s,
      s.after_capture_s, c.frames_taken, c.frames_skipped, s.incomplete_frames, s.retaken_frames);
  return t.str() + line;
}

// The map, the calibration and the validation views.
std::string ResultText(const ProcessReport& p) {
  const ReconstructionReport& r = p.reconstruction;
  std::ostringstream t;
  char line[256];
  std::snprintf(line, sizeof line,
                "map svbrdf.exr: %d x %d pixels of %.3f mm; %ld valid (%.1f%%); not valid: %ld "
                "with no observation, %ld too few, %ld poorly conditioned\n",
                p.reference_width, p.reference_height, p.pixel_size_mm, r.valid,
                r.pixels ? 100.0 * double(r.valid) / double(r.pixels) : 0.0, r.no_observation,
                r.too_few_observations, r.poorly_conditioned);
  t << line;
  if (r.off_spectralon_observations > 0) {
    std::snprintf(line, sizeof line,
                  "  %ld observations dropped where the Spectralon did not read its board at the "
                  "point (off its edge, or shadowed): cover the sample with the board\n",
                  r.off_spectralon_observations);
    t << line;
  }
  if (r.method == ReconstructionMethod::kPooled) {
    t << r.model.Summary();
    std::snprintf(line, sizeof line, "pooled: %ld pixels with their group's prior, %ld alone\n",
                  r.pooled, r.pixels - r.pooled);
    t << line;
  }
  if (r.normals_searched) t << r.NormalsSummary() << "; the map's normal_status says which\n";
  if (r.ManyNormalsRefused()) t << "  " << r.NormalsWarning() << "\n";
  const SessionCalibration& c = p.calibration;
  int found = 0;
  for (const BoardPoseResult& b : c.boards) found += b.found;
  if (c.intrinsics_captures > 0)
    std::snprintf(line, sizeof line,
                  "calibration: %s from %s, residual %.3f px, projection uncertainty %.3f px at "
                  "the centre, %.3f px worst; board found at %d of %zu poses\n",
                  c.camera.lensmodel_name().c_str(), c.intrinsics_from.c_str(), c.intrinsics_rms_px,
                  c.uncertainty_centre_px, c.uncertainty_worst_px, found, c.boards.size());
  else
    std::snprintf(line, sizeof line,
                  "calibration: %s calibrated before (%s); board found at %d of %zu poses\n",
                  c.camera.lensmodel_name().c_str(), c.intrinsics_from.c_str(), found,
                  c.boards.size());
  t << line;
  for (const std::string& w : c.warnings) t << "  WARNING: " << w << "\n";
  if (p.chart) {
    const ChartPatchFit* worst = nullptr;
    for (const ChartPatchFit& patch : p.chart->patches)
      if (patch.used && (!worst || patch.delta_e2000 > worst->delta_e2000)) worst = &patch;
    std::snprintf(line, sizeof line,
                  "colour chart: matrix fitted from %d of 24 patches, residual CIEDE2000 median "
                  "%.2f, worst %.2f (%s)\n",
                  p.chart->used, p.chart->median_delta_e2000, p.chart->max_delta_e2000,
                  worst ? worst->name.c_str() : "-");
    t << line;
    if (p.chart->turned != ChartTurn::kNone)
      t << "  WARNING: the chart was laid turned " << ChartTurnDegrees(p.chart->turned)
        << " degrees counter-clockwise from its layout (where dark skin belongs at the -x, -y "
           "corner); fitted as laid\n";
    for (const ChartPatchFit& patch : p.chart->patches)
      if (!patch.used)
        t << "  WARNING: chart patch " << patch.name << " left out: " << patch.dropped << "\n";
  } else if (p.rec709_from_camera) {
    t << "colour matrix: given in the plan (camera.colour_matrix)\n";
  }
  if (!p.validation.empty())
    t << "validation views: the map's render read where the capture was read (each view pixel "
         "at its own point; docs/reconstruction.md, \"A prediction sampled as the capture "
         "was\")\n";
  for (const ValidationSummary& v : p.validation) {
    std::snprintf(line, sizeof line,
                  "validation %s: relative RMS error %.3f, median per pixel %.3f, median "
                  "CIEDE2000 %.2f over %ld pixels (%s)\n",
                  v.name.c_str(), v.relative_rms, v.median_relative, v.median_delta_e2000, v.pixels,
                  v.render.c_str());
    t << line;
    // One pixel carrying much of an RMS is worth a look before the figure is read as the map's.
    if (v.worst_share >= kWorstPixelShareShown) {
      std::snprintf(line, sizeof line,
                    "  %.0f%% of its squared error from one pixel, at (%d, %d) of the map\n",
                    100 * v.worst_share, v.worst_x, v.worst_y);
      t << line;
    }
  }
  return t.str();
}

// The simulated session against its truth.
std::string TruthText(const SessionReport& s) {
  if (!s.scored) return "";
  std::ostringstream t;
  char line[256];
  std::snprintf(line, sizeof line,
                "against the ground truth: median per-pixel log-space RMSE %.4f (valid pixels "
                "%.4f); homogeneous result for the same materials and directions %.4f\n",
                s.score.median_log_rmse, s.score.median_log_rmse_valid,
                s.homogeneous_median_log_rmse);
  t << line;
  if (s.colour()) {
    const std::array<double, 3>& c = s.score.channel_median_log_rmse;
    std::snprintf(line, sizeof line,
                  "  per channel R %.4f, G %.4f, B %.4f; diffuse colour against the truth: median "
                  "CIEDE2000 %.2f\n",
                  c[0], c[1], c[2], s.score.albedo_delta_e2000_median);
    t << line;
  }
  std::snprintf(line, sizeof line,
                "calibrated geometry against the true one: misalignment median %.3f px, worst "
                "%.3f px; the camera centre from the board alone off by %.2f deg median, %.2f "
                "deg worst\n",
                s.alignment_median_px, s.alignment_max_px, s.board_eye_error_median_deg,
                s.board_eye_error_max_deg);
  t << line;
  if (const auto& n = s.normals; n && n->relief_pixels == 0) {
    std::snprintf(line, sizeof line,
                  "  normals on a flat sample: false tilt %.2f deg median over %ld pixels; %ld "
                  "refused, %ld without evidence\n",
                  n->median_tilt_deg_flat, n->flat_pixels, n->refused, n->no_evidence);
    t << line;
  } else if (n) {
    std::snprintf(line, sizeof line,
                  "  normals against the relief: median error %.2f deg over it (%.2f assumed "
                  "flat; %.2f over %ld pixels of one material, %.2f over %ld at ink edges), false "
                  "tilt %.2f deg on flat areas; %ld refused, %ld without evidence\n",
                  n->median_error_deg_relief, n->median_error_deg_relief_assumed_flat,
                  n->median_error_deg_relief_one_material, n->relief_pixels_one_material,
                  n->median_error_deg_relief_ink_edges, n->relief_pixels_ink_edges,
                  n->median_tilt_deg_flat, n->refused, n->no_evidence);
    t << line;
    std::snprintf(line, sizeof line,
                  "  normals' uncertainty: median %.2f deg over the estimated pixels; over the "
                  "relief, error %.2f deg median where it is %.0f deg or less (%ld pixels), %.2f "
                  "where more (%ld)\n",
                  n->median_uncertainty_deg, n->median_error_deg_relief_certain, kCertainNormalDeg,
                  n->relief_pixels_certain, n->median_error_deg_relief_uncertain,
                  n->relief_pixels_uncertain);
    t << line;
  }
  for (const SessionReport::ValidationTruth& v : s.validation_truth) {
    std::snprintf(line, sizeof line,
                  "  validation %s: the truth against the capture: relative RMS %.3f, median "
                  "CIEDE2000 %.2f (the capture's noise and sampling); the map against the "
                  "truth: %.3f, %.2f\n",
                  v.name.c_str(), v.capture_relative_rms, v.capture_delta_e2000, v.map_relative_rms,
                  v.map_delta_e2000);
    t << line;
  }
  const std::vector<double>& per_material = s.score.material_median_log_rmse;
  for (std::size_t m = 0; m < per_material.size(); ++m) {
    std::snprintf(line, sizeof line,
                  "  material %zu %-24s per-pixel median %.4f, homogeneous %.4f\n", m,
                  m < s.materials.size() ? s.materials[m].c_str() : "", per_material[m],
                  m < s.homogeneous_log_rmse.size() ? s.homogeneous_log_rmse[m] : 0.0);
    t << line;
    if (s.normals && m < s.normals->material_median_tilt_deg_flat.size() &&
        std::isfinite(s.normals->material_median_tilt_deg_flat[m])) {
      std::snprintf(line, sizeof line,
                    "    normals: false tilt %.2f deg median on its flat pixels\n",
                    s.normals->material_median_tilt_deg_flat[m]);
      t << line;
    }
    if (s.colour() && m < s.score.material_albedo_delta_e2000_median.size()) {
      std::snprintf(line, sizeof line,
                    "    diffuse colour: median CIEDE2000 %.2f over its pixels, %.2f of their "
                    "mean colour\n",
                    s.score.material_albedo_delta_e2000_median[m],
                    s.score.material_albedo_mean_delta_e2000[m]);
      t << line;
    }
  }
  return t.str();
}

}  // namespace

std::string SessionReport::Text() const {
  return "session " + session + " (plan " + plan + ", backend " + backend + ")\n\n" +
         TimeText(*this) + ResultText(process) + TruthText(*this);
}

void WriteReport(const SessionReport& report, const std::string& session_dir) {
  const std::string json = report.Json(), text = report.Text();
  WriteFileAtomically(session_dir + "/report.json", json.data(), json.size());
  WriteFileAtomically(session_dir + "/report.txt", text.data(), text.size());
}

}  // namespace acq
