#include "session/process.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "acq/correspondence_source.h"
#include "acq/hdr.h"
#include "acq/map_render.h"
#include "acq/plan_record.h"
#include "brdf/basis_file.h"
#include "calib/correspondence.h"
#include "calib/synthetic_board.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/seconds_since.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"
#include "session/pose_hdr.h"
#include "session/view_correspondence.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

// A pose's R, G and B in linear Rec. 709: a mono camera's one image thrice; a colour camera's
// demosaiced camera RGB through the plan's colour matrix (the light's colour stays, for the
// Spectralon captures to divide out channel by channel).
std::array<ViewImage, 3> Channels(HdrImage&& hdr,
                                  const std::optional<Eigen::Matrix3d>& rec709_from_camera) {
  std::vector<std::uint8_t> unusable(hdr.flag.size());
  for (std::size_t i = 0; i < unusable.size(); ++i) unusable[i] = hdr.flag[i] != kHdrOk;
  if (hdr.channels == 1) {
    const ViewImage image(hdr.width, hdr.height, std::move(hdr.radiance), std::move(unusable));
    return {image, image, image};  // the same pixels thrice: a mono camera
  }
  if (!rec709_from_camera)
    throw UserError("camera.colour_matrix",
                    "the session's images are colour, the plan has no colour matrix or chart",
                    "give camera.colour_chart or camera.colour_matrix (docs/colour.md)");
  // In place: the three planes stay one buffer, shared by the three channels' images.
  const Eigen::Matrix3f m = rec709_from_camera->cast<float>();
  const std::size_t n = std::size_t(hdr.width) * std::size_t(hdr.height);
  float* rgb = hdr.radiance.data();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
    const Eigen::Vector3f camera(rgb[i], rgb[n + i], rgb[2 * n + i]);
    const Eigen::Vector3f rec709 = m * camera;
    for (int c = 0; c < 3; ++c) rgb[c * n + i] = rec709[c];
  }
  const auto planes = std::make_shared<const std::vector<float>>(std::move(hdr.radiance));
  const auto flags = std::make_shared<const std::vector<std::uint8_t>>(std::move(unusable));
  return {ViewImage(hdr.width, hdr.height, planes, 0, flags),
          ViewImage(hdr.width, hdr.height, planes, 1, flags),
          ViewImage(hdr.width, hdr.height, planes, 2, flags)};
}

// The views of `step` (with the Spectralon captures of `spectralon_step` where there are any):
// each pose's correspondence map, from the camera pose its board capture gave.
std::vector<SessionView> ViewsOf(const Plan& plan, Step step, Step spectralon_step,
                                 SessionReference& reference, const SessionGeometry& geometry,
                                 const SessionFrames& session, PrecomputedStages& precomputed,
                                 ProcessReport* report) {
  const SessionCalibration& calibration = report->calibration;
  std::map<int, PoseHdr> sample = MergeStep(step, session, &report->hdr_s, &precomputed.poses);
  std::map<int, PoseHdr> spectralon =
      plan.spectralon ? MergeStep(spectralon_step, session, &report->hdr_s, &precomputed.poses)
                      : std::map<int, PoseHdr>();
  double correspondence_s = 0;
  std::vector<SessionView> views;
  for (auto& [pose, p] : sample) {
    const BoardPoseResult* board = calibration.PoseOf(step, pose);
    if (!board) {
      report->views_left_out.push_back(PoseName(step, pose));
      continue;
    }
    const calib::CalibratedView calibrated =
        CalibratedViewOf(plan, calibration.camera, *board, p.arms);
    SessionView view;
    view.name = p.direction.empty() ? PoseName(step, pose) : p.direction;
    view.pose = pose;
    if (auto known = precomputed.correspondence.extract({step, pose})) {
      view.correspondence = std::move(known.mapped());
    } else {
      view.correspondence =
          PoseCorrespondence(session.dir, step, pose, reference, calibrated, &correspondence_s);
    }
    view.sample = Channels(std::move(p.hdr), report->rec709_from_camera);
    if (plan.spectralon) {
      const auto s = spectralon.find(pose);
      if (s == spectralon.end())
        throw UserError(session.dir, "no Spectralon capture of " + view.name,
                        "run acqd again with the same plan to capture what is missing");
      view.spectralon = Channels(std::move(s->second.hdr), report->rec709_from_camera);
    }
    view.light_in_sample_mm = calibrated.light_in_sample_mm;
    view.light_intensity = geometry.light_intensity;
    views.push_back(std::move(view));
  }
  report->correspondence_s += correspondence_s;
  return views;
}

// The map's prediction beside the capture, one PNG with one exposure for both.
void WriteComparison(const ValidationResult& r, const std::string& path) {
  RgbImage both{2 * r.predicted.width, r.predicted.height,
                std::vector<float>(r.predicted.rgb.size() * 2, 0.0f)};
  for (int y = 0; y < both.height; ++y)
    for (int x = 0; x < r.predicted.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::size_t from = (std::size_t(y) * r.predicted.width + x) * 3 + c;
        both.rgb[(std::size_t(y) * both.width + x) * 3 + c] = r.predicted.rgb[from];
        both.rgb[(std::size_t(y) * both.width + x + r.predicted.width) * 3 + c] =
            r.captured.rgb[from];
      }
  WritePng(both, path);
}

// The colour matrix from the chart captured at the sample's first pose, with the Spectralon
// and the board captured there.
ChartFit FitSessionChart(const Plan& plan, const SessionFrames& session,
                         const PrecomputedStages& precomputed, ProcessReport* report) {
  const std::string where = session.dir + ": the colour chart";
  const BoardPoseResult* board = report->calibration.PoseOf(Step::kChart, 0);
  if (!board)
    throw UserError(where, "the board at the chart's pose (board_000) was not found",
                    "capture the session again with the board visible at its first pose");
  auto merged = [&](Step step) {
    const auto known = precomputed.poses.find({step, 0});
    if (known != precomputed.poses.end()) return known->second;
    const std::vector<CatalogFrame> frames = session.OfPose(step, 0);
    if (frames.empty())
      throw UserError(where, std::string("no ") + ToString(step) + " capture at the chart's pose",
                      "run acqd again with the same plan to capture what is missing");
    return MergePose(session.dir, step, 0, frames, &report->hdr_s);
  };
  const PoseHdr chart = merged(Step::kChart), white = merged(Step::kSpectralon);
  const calib::CalibratedView view =
      CalibratedViewOf(plan, report->calibration.camera, *board, chart.arms);
  const SampleToImage to_image =
      [&view](const Eigen::Vector2d& p) -> std::optional<Eigen::Vector2d> {
    const Eigen::Vector3d in_cam = view.cam_from_sample * Eigen::Vector3d(p.x(), p.y(), 0);
    if (!(in_cam.z() > 0)) return std::nullopt;
    return view.camera.Project(in_cam);
  };
  return FitColourChart(chart.hdr, white.hdr, to_image, where);
}

// The map from the sample's views into svbrdf.exr. The views are released on return (their
// images are 2 GB at 2048 x 2048), before the validation needs memory of its own.
ReconstructionReport ReconstructMap(const Plan& plan, const MappedBasis& mapped,
                                    std::vector<SessionView> views, double pixel_size_mm,
                                    const std::string& dir) {
  CorrespondenceSource source(std::move(views), pixel_size_mm);
  ReconstructionOptions options;
  options.solve.components = plan.reconstruction.components;
  options.solve.eta = plan.reconstruction.eta;
  options.solve.lookup = plan.reconstruction.lookup;
  options.solve.row_tile = plan.reconstruction.row_tile;
  options.method = plan.reconstruction.method;
  options.pooled.groups = plan.reconstruction.groups;
  options.pooled.design_sigma_deg = plan.reconstruction.design_sigma_deg;
  options.normals.enabled = plan.reconstruction.normals;
  options.normals.prior = plan.reconstruction.normals_prior;
  options.normals.mixed_pixels = plan.reconstruction.normals_mixed_pixels;
  options.normals.trimmed_views = plan.reconstruction.normals_trimmed_views;
  options.normals.max_uncertainty_deg = plan.reconstruction.normals_max_uncertainty_deg;
  options.normals.evidence = plan.reconstruction.normals_evidence;
  options.normals.score_min_cos = plan.reconstruction.normals_score_min_cos;
  options.normals.view_weights = plan.reconstruction.normals_view_weights;
  options.normals.min_tilt_deg = plan.reconstruction.normals_min_tilt_deg;
  options.normals.mixed_same_group = plan.reconstruction.normals_mixed_same_group;
  options.normals.same_centre = plan.reconstruction.normals_same_centre;
  options.normals.confirmation = plan.reconstruction.normals_confirmation;
  options.progress = false;
  SvbrdfMapInfo info;
  info.basis = plan.reconstruction.basis_file;
  info.basis_crc32 = mapped.Checksum();
  info.camera_model = dir + "/calibration/camera.cameramodel";
  if (plan.reconstruction.pixel_footprint) info.pixel_spread_px = CameraPixelSpreadPx(plan);
  ReconstructionReport report =
      Reconstruct(mapped.View(), source, options, info, dir + "/svbrdf.exr");
  report.off_spectralon_observations = source.OffBoardObservations();
  return report;
}

}  // namespace

ProcessReport ProcessSession(const Plan& plan, SessionCatalog& catalog,
                             const SessionGeometry& geometry, PrecomputedStages precomputed) {
  ProcessReport report;
  const std::string dir = catalog.directory();
  const SessionFrames session = SessionFrames::Of(catalog);
  for (const char* sub : {"hdr", "correspondence", "calibration", "renders"})
    fs::create_directories(fs::path(dir) / sub);
  auto start = SteadyClock::now();
  if (precomputed.calibration) {
    report.calibration = std::move(*precomputed.calibration);
  } else {
    double calibration_hdr_s = 0;
    report.calibration = CalibrateSession(plan, session, &calibration_hdr_s);
    report.hdr_s += calibration_hdr_s;
    report.calibration_s = SecondsSince(start) - calibration_hdr_s;
  }
  const calib::CameraModel& camera = report.calibration.camera;

  // The reference view, the pixel grid the maps are on.
  SessionReference reference(ReferenceViewOf(plan, camera));
  report.pixel_size_mm = plan.gantry.camera_distance_mm / camera.intrinsics()[0];
  report.reference_width = reference.view().width;
  report.reference_height = reference.view().height;

  report.rec709_from_camera = plan.camera.rec709_from_camera;
  if (plan.camera.colour_chart == CameraSpec::Chart::kFitted) {
    report.chart = FitSessionChart(plan, session, precomputed, &report);
    report.rec709_from_camera = report.chart->rec709_from_camera;
    catalog.Event("info", "colour matrix fitted from the chart");
  }
  std::vector<SessionView> views = ViewsOf(plan, Step::kSample, Step::kSpectralon, reference,
                                           geometry, session, precomputed, &report);
  if (views.empty()) throw UserError(dir, "no sample frames to process");

  start = SteadyClock::now();
  const MappedBasis mapped = MappedBasis::Open(plan.reconstruction.basis_file);
  report.reconstruction = ReconstructMap(plan, mapped, std::move(views), report.pixel_size_mm, dir);
  report.reconstruction_s = SecondsSince(start);
  catalog.Event("info", "reconstructed: svbrdf.exr");

  // The renders: the map's quick looks, then each validation view beside its capture.
  start = SteadyClock::now();
  const SvbrdfMap map = ReadSvbrdfMap(dir + "/svbrdf.exr");
  WriteQuickLooks(map, mapped.View(), dir + "/renders", "quicklook_");
  report.validation_s = SecondsSince(start);
  if (plan.validation.empty()) return report;
  std::vector<SessionView> checks = ViewsOf(plan, Step::kValidation, Step::kSpectralonValidation,
                                            reference, geometry, session, precomputed, &report);
  start = SteadyClock::now();
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const std::string name = checks[i].name;
    // Named by the validation pose it shows: a pose left out (its board not found) leaves a gap
    // in the numbers, never shifts the names of the others.
    const std::string stem = "renders/" + PoseName(Step::kValidation, checks[i].pose);
    const std::string render = stem + ".png";
    // The capture and its directions kept, for models made from the map later (acq export).
    const ValidationData data = CaptureOfView(map, std::move(checks[i]));
    const ValidationResult r =
        Compare(data, MapPixelBrdf(map, mapped.View(), plan.reconstruction.lookup));
    WriteValidationData(data, dir + "/" + stem + ".exr", &r.predicted);
    ValidationSummary s{name,   r.pixels,  r.relative_rms, r.median_relative, r.median_delta_e2000,
                        render, r.worst_x, r.worst_y,      r.worst_share};
    WriteComparison(r, dir + "/" + s.render);
    report.validation.push_back(s);
  }
  report.validation_s += SecondsSince(start);
  return report;
}

}  // namespace acq
