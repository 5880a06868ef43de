#include "acq/plan_record.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "core/angles.h"
#include "core/error.h"
#include "core/pixel_footprint.h"
#include "core/sha256.h"
#include "io/session_catalog.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSettingsFile = "plan_settings.tsv";
// Files up to this size are copied into the session with the plan (directions, camera models,
// material fits); larger ones (a basis) are recorded by checksum only.
constexpr std::uintmax_t kCopyLimitBytes = 16u << 20;
// Replays of replays followed back to the camera that took the frames: no further than this.
constexpr int kMaxReplayDepth = 16;

std::string Number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.12g", v);
  return text;
}

std::string Numbers(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : " ") + Number(v);
  return out;
}

std::string FileValue(const std::string& path) {
  return path.empty() ? ""
                      : "sha256:" + Sha256OfFile(path) + " " + fs::path(path).filename().string();
}

std::string DirectionValue(const Direction& d) {
  const RusinkiewiczAngles& a = d.angles;
  return Numbers({RadToDeg(a.theta_h), RadToDeg(a.theta_d), RadToDeg(a.phi_d)});
}

class Settings {
 public:
  void Capture(const std::string& key, const std::string& value) {
    out.push_back({PlanSetting::Kind::kCapture, key, value});
  }
  void Processing(const std::string& key, const std::string& value) {
    out.push_back({PlanSetting::Kind::kProcessing, key, value});
  }
  void Directions(const std::string& key, const std::vector<Direction>& directions) {
    Capture(key + ".count", std::to_string(directions.size()));
    for (std::size_t i = 0; i < directions.size(); ++i)
      Capture(key + "[" + std::to_string(i + 1) + "]", DirectionValue(directions[i]));
  }
  std::vector<PlanSetting> out;
};

const char* KindName(PlanSetting::Kind k) {
  return k == PlanSetting::Kind::kCapture ? "capture" : "processing";
}

std::vector<PlanSetting> ReadSettings(const std::string& path) {
  std::ifstream in(path);
  std::vector<PlanSetting> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t a = line.find('\t'), b = line.find('\t', a + 1);
    if (a == std::string::npos || b == std::string::npos)
      throw UserError(path + ":" + std::to_string(n), "not a plan setting line",
                      "this file is acqd's own; restore it from a backup or start a new session");
    const std::string kind = line.substr(0, a);
    if (kind != KindName(PlanSetting::Kind::kCapture) &&
        kind != KindName(PlanSetting::Kind::kProcessing))
      throw UserError(path + ":" + std::to_string(n), "unknown setting kind '" + kind + "'",
                      "this file is acqd's own; restore it from a backup or start a new session");
    out.push_back({kind == KindName(PlanSetting::Kind::kCapture) ? PlanSetting::Kind::kCapture
                                                                 : PlanSetting::Kind::kProcessing,
                   line.substr(a + 1, b - a - 1), line.substr(b + 1)});
  }
  return out;
}

void WriteSettings(const std::vector<PlanSetting>& settings, const std::string& path) {
  std::ostringstream text;
  text << "# kind\tkey\tvalue: the plan this session was captured with (acqd, issue 22)\n";
  for (const PlanSetting& s : settings)
    text << KindName(s.kind) << '\t' << s.key << '\t' << s.value << '\n';
  const std::string bytes = text.str();
  WriteFileAtomically(path, bytes.data(), bytes.size());
}

// The plan file and the files it names that are small enough, copied into the session.
void CopyPlanFiles(const Plan& plan, const std::string& session) {
  const std::string text = [&] {
    std::ifstream in(plan.path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  WriteFileAtomically(session + "/plan.yaml", text.data(), text.size());
  // Where its relative paths point from: `acq process` reads the copy relative to this folder.
  const std::string folder =
      fs::absolute(fs::path(plan.path)).parent_path().lexically_normal().string() + "\n";
  WriteFileAtomically(session + "/" + kPlanFolderFile, folder.data(), folder.size());
  std::vector<std::string> files = {plan.directions_file, plan.validation_file,
                                    plan.calibration.intrinsics_file};
  files.insert(files.end(), plan.sim.materials.begin(), plan.sim.materials.end());
  if (plan.sim.sample_file) files.push_back(plan.sim.sample_file->path);
  if (plan.sim.relief) files.push_back(plan.sim.relief->height_map);
  std::error_code ec;
  fs::create_directories(session + "/plan_files", ec);
  for (const std::string& f : files) {
    if (f.empty() || !fs::is_regular_file(f, ec) || fs::file_size(f, ec) > kCopyLimitBytes)
      continue;
    fs::copy_file(f, session + "/plan_files/" + fs::path(f).filename().string(),
                  fs::copy_options::overwrite_existing, ec);
  }
}

}  // namespace

std::vector<PlanSetting> PlanSettings(const Plan& plan) {
  Settings s;
  s.Capture("backend", BackendName(plan.backend));
  if (plan.backend == Backend::kReplay) s.Capture("replay", plan.replay_session);
  s.Capture("sample.size_mm", Numbers({plan.sample.width_mm, plan.sample.height_mm}));
  if (plan.backend == Backend::kUsbAravis) s.Capture("gantry.usb", plan.gantry.usb.Describe());
  const DirectionConstraints& c = plan.gantry.motion.constraints;
  s.Capture("gantry.limits", Numbers({RadToDeg(c.max_camera_zenith), RadToDeg(c.max_light_zenith),
                                      RadToDeg(c.min_separation)}));
  const GantryMotion& m = plan.gantry.motion;
  s.Capture("gantry.axes",
            Numbers({RadToDeg(m.theta.speed), RadToDeg(m.theta.acceleration), RadToDeg(m.phi.speed),
                     RadToDeg(m.phi.acceleration), m.settle_s}));
  // Recorded when not the fastest (what sessions before it were planned with), so that those
  // resume and replay as they were captured.
  if (m.half_vector_azimuths != HalfVectorAzimuths::kFastest)
    s.Capture("gantry.half_vector_azimuths", ToString(m.half_vector_azimuths));
  s.Capture("gantry.camera_distance_mm", Number(plan.gantry.camera_distance_mm));
  s.Capture("gantry.light_distance_mm", Number(plan.gantry.light_distance_mm));
  s.Capture("camera.id", plan.camera.id);
  s.Capture("camera.pixel_format", PixelFormatName(plan.camera.settings.pixel_format));
  s.Capture("camera.gain_db", Number(plan.camera.settings.gain_db));
  s.Capture("camera.hdr", plan.camera.auto_bracket ? "auto" : Numbers(plan.camera.bracket_us));
  s.Directions("directions", plan.directions);
  s.Directions("directions.validation", plan.validation);
  s.Capture("calibration.intrinsics_captures",
            std::to_string(plan.calibration.intrinsics_captures));
  s.Capture("calibration.board",
            Numbers({double(plan.calibration.board_width_n),
                     double(plan.calibration.board_height_n), plan.calibration.board_spacing_mm}));
  s.Capture("spectralon", plan.spectralon ? "true" : "false");
  if (plan.camera.ChartCaptured()) s.Capture("camera.colour_chart", "true");  // fitted or not
  if (plan.backend == Backend::kSim) {
    for (std::size_t i = 0; i < plan.sim.materials.size(); ++i)
      s.Capture("sim.materials[" + std::to_string(i + 1) + "]", FileValue(plan.sim.materials[i]));
    s.Capture("sim.seed", std::to_string(plan.sim.seed));
    if (const std::optional<SampleFile>& f = plan.sim.sample_file)
      s.Capture(f->kind == SampleFile::Kind::kLabels ? "sim.sample.labels" : "sim.sample.weights",
                FileValue(f->path));
    else if (plan.sim.sample != SampleKind::kCard)
      s.Capture("sim.sample", SampleKindName(plan.sim.sample));
    s.Capture("sim.light_intensity", Number(plan.sim.light_intensity));
    // The simulated sensor's filter and light change every frame (a resume with another would
    // mix two cameras' frames in one map). Recorded where not the mono camera's white light, so
    // that the sessions recorded before colour existed still resume.
    const Cfa filter = plan.sim.camera_filter.value_or(CfaOf(plan.camera.settings.pixel_format));
    if (filter != Cfa::kNone) s.Capture("sim.camera_filter", CfaName(filter));
    if (const auto& rgb = plan.sim.light_rgb)
      s.Capture("sim.light_rgb", Numbers({rgb->x(), rgb->y(), rgb->z()}));
    // So are the camera's pixel samples (recorded where not 1, as the sessions before it were).
    if (plan.sim.pixel_samples != 1)
      s.Capture("sim.pixel_samples", std::to_string(plan.sim.pixel_samples));
    if (const auto& relief = plan.sim.relief) {
      if (!relief->height_map.empty())
        s.Capture("sim.relief.height_map", FileValue(relief->height_map));
      else
        s.Capture("sim.relief", Numbers({relief->slope_deg, relief->fibre_deg}));
    }
    // The chart's frame changes with how it is laid (recorded only when not as it should be).
    if (const auto& box = plan.sim.chart.covered_mm)
      s.Capture("sim.chart.covered_mm", Numbers({(*box)[0], (*box)[1], (*box)[2], (*box)[3]}));
    if (!plan.sim.chart.laid) s.Capture("sim.chart.laid", "false");
    if (plan.sim.chart.turned != ChartTurn::kNone)
      s.Capture("sim.chart.turned_deg", std::to_string(ChartTurnDegrees(plan.sim.chart.turned)));
  }
  // Processing only: the frames stay what they are.
  // The colour matrix is applied to the HDR images when processing (a camera characterised
  // later may reprocess its sessions with it).
  if (plan.camera.rec709_from_camera) {
    const Eigen::Matrix3d& m = *plan.camera.rec709_from_camera;
    std::vector<double> rows;  // row by row, as the plan gives it
    for (int i = 0; i < 9; ++i) rows.push_back(m(i / 3, i % 3));
    s.Processing("camera.colour_matrix", Numbers(rows));
  }
  s.Processing("calibration.camera_model", FileValue(plan.calibration.intrinsics_file));
  s.Processing("calibration.lensmodel", plan.calibration.lensmodel);
  s.Processing("reconstruction.basis", FileValue(plan.reconstruction.basis_file));
  s.Processing("reconstruction.k", std::to_string(plan.reconstruction.components));
  s.Processing("reconstruction.eta", Number(plan.reconstruction.eta));
  s.Processing("reconstruction.lookup", RowLookupName(plan.reconstruction.lookup));
  s.Processing("reconstruction.row_tile", std::to_string(plan.reconstruction.row_tile));
  s.Processing("reconstruction.method", ReconstructionMethodName(plan.reconstruction.method));
  s.Processing("reconstruction.groups", std::to_string(plan.reconstruction.groups));
  // Recorded when not the default, so that the sessions recorded before they existed compare
  // unchanged.
  if (plan.reconstruction.design_sigma_deg != kDefaultDesignSigmaDeg)
    s.Processing("reconstruction.design_sigma_deg", Number(plan.reconstruction.design_sigma_deg));
  if (plan.reconstruction.normals) s.Processing("reconstruction.normals", "true");
  if (plan.reconstruction.normals_prior != kDefaultNormalsPrior)
    s.Processing("reconstruction.normals_prior", Number(plan.reconstruction.normals_prior));
  if (plan.reconstruction.normals_mixed_pixels != kDefaultNormalsMixedPixels)
    s.Processing("reconstruction.normals_mixed_pixels",
                 plan.reconstruction.normals_mixed_pixels ? "true" : "false");
  if (plan.reconstruction.normals_trimmed_views != kDefaultNormalsTrimmedViews)
    s.Processing("reconstruction.normals_trimmed_views",
                 std::to_string(plan.reconstruction.normals_trimmed_views));
  if (plan.reconstruction.normals_max_uncertainty_deg != kDefaultNormalsMaxUncertaintyDeg)
    s.Processing("reconstruction.normals_max_uncertainty_deg",
                 Number(plan.reconstruction.normals_max_uncertainty_deg));
  if (plan.reconstruction.normals_evidence != kDefaultNormalsEvidence)
    s.Processing("reconstruction.normals_evidence", Number(plan.reconstruction.normals_evidence));
  if (plan.reconstruction.normals_min_tilt_deg != kDefaultNormalsMinTiltDeg)
    s.Processing("reconstruction.normals_min_tilt_deg",
                 Number(plan.reconstruction.normals_min_tilt_deg));
  if (plan.reconstruction.normals_view_weights != kDefaultNormalsViewWeights)
    s.Processing("reconstruction.normals_view_weights",
                 plan.reconstruction.normals_view_weights ? "true" : "false");
  if (plan.reconstruction.normals_same_centre != kDefaultNormalsSameCentre)
    s.Processing("reconstruction.normals_same_centre",
                 plan.reconstruction.normals_same_centre ? "true" : "false");
  if (plan.reconstruction.normals_mixed_same_group != kDefaultNormalsMixedSameGroup)
    s.Processing("reconstruction.normals_mixed_same_group",
                 plan.reconstruction.normals_mixed_same_group ? "true" : "false");
  if (plan.reconstruction.normals_score_min_cos != kDefaultNormalsScoreMinCos)
    s.Processing("reconstruction.normals_score_min_cos",
                 Number(plan.reconstruction.normals_score_min_cos));
  if (plan.reconstruction.normals_confirmation != kDefaultNormalsConfirmation)
    s.Processing("reconstruction.normals_confirm",
                 NormalConfirmationName(plan.reconstruction.normals_confirmation));
  if (!plan.reconstruction.pixel_footprint) s.Processing("reconstruction.pixel_footprint", "false");
  return s.out;
}

namespace {

struct SettingsComparison {
  std::vector<std::string> capture;     // "key: was -> is", settings that change the capture
  std::vector<std::string> processing;  // the same for processing settings
};

bool EverySetting(const std::string&) {
  return true;
}

// Settings whose key `compared` rejects are left out on both sides.
SettingsComparison Compare(const std::vector<PlanSetting>& now, const std::string& path,
                           const std::function<bool(const std::string&)>& compared = EverySetting) {
  std::map<std::string, PlanSetting> recorded;
  for (const PlanSetting& s : ReadSettings(path))
    if (compared(s.key)) recorded[s.key] = s;
  auto change = [](const std::string& key, const std::string& was, const std::string& is) {
    return key + ": " + (was.empty() ? "(none)" : was) + " -> " + (is.empty() ? "(none)" : is);
  };
  SettingsComparison c;
  std::set<std::string> seen;
  for (const PlanSetting& s : now) {
    if (!compared(s.key)) continue;
    seen.insert(s.key);
    const auto r = recorded.find(s.key);
    const std::string was = r == recorded.end() ? "" : r->second.value;
    if (was == s.value) continue;
    (s.kind == PlanSetting::Kind::kCapture ? c.capture : c.processing)
        .push_back(change(s.key, was, s.value));
  }
  for (const auto& [key, s] : recorded)
    if (!seen.count(key) && s.kind == PlanSetting::Kind::kCapture)
      c.capture.push_back(change(key, s.value, ""));
  return c;
}

// The capture settings of `plan` whose keys `compared` accepts that differ from those `session`
// recorded; none when it has no record.
std::vector<std::string> CaptureDifferencesIn(
    const Plan& plan, const std::string& session,
    const std::function<bool(const std::string&)>& compared) {
  const std::string path = session + "/" + kSettingsFile;
  if (!fs::exists(path)) return {};
  return Compare(PlanSettings(plan), path, compared).capture;
}

}  // namespace

std::vector<std::string> PlanRecordFiles() {
  return {"plan.yaml", "plan_files", kSettingsFile, kPlanFolderFile};
}

std::vector<std::string> CaptureDifferences(const Plan& plan, const std::string& session) {
  return CaptureDifferencesIn(plan, session, EverySetting);
}

std::string ListedChanges(const std::vector<std::string>& changes, const std::string& which) {
  constexpr std::size_t kListed = 12;
  std::string s =
      std::to_string(changes.size()) + " setting" + (changes.size() > 1 ? "s" : "") + which + ":";
  for (std::size_t i = 0; i < changes.size() && i < kListed; ++i) s += "\n  " + changes[i];
  return s + (changes.size() > kListed ? "\n  ..." : "") + "\n";
}

double CameraPixelSpreadPx(const Plan& plan) {
  switch (plan.backend) {
    case Backend::kSim:
      return PixelSamplesSpreadPx(plan.sim.pixel_samples);
    case Backend::kUsbAravis:
      return kWholePixelSpreadPx;
    case Backend::kReplay:
      break;
  }
  // A replay serves the frames of the session it replays: that session's camera took them (and
  // a replay's, the camera of the session that one replayed).
  std::string session = plan.replay_session;
  for (int depth = 0; depth < kMaxReplayDepth; ++depth) {
    const std::string path = session + "/" + kSettingsFile;
    if (!fs::exists(path)) return kWholePixelSpreadPx;  // recorded before plans were: a real one
    std::string backend, replayed, samples = "1";       // sim.pixel_samples recorded where not 1
    for (const PlanSetting& s : ReadSettings(path)) {
      if (s.key == "backend") backend = s.value;
      if (s.key == "replay") replayed = s.value;
      if (s.key == "sim.pixel_samples") samples = s.value;
    }
    if (backend == BackendName(Backend::kSim))
      return PixelSamplesSpreadPx(std::atoi(samples.c_str()));
    if (backend != BackendName(Backend::kReplay) || replayed.empty()) return kWholePixelSpreadPx;
    session = replayed;
  }
  return kWholePixelSpreadPx;
}

std::vector<std::string> ReplayDifferences(const Plan& plan, const std::string& session) {
  const auto asks_for_frames = [](const std::string& key) {
    return key != "backend" && key != "replay" && key.rfind("sim.", 0) != 0;
  };
  return CaptureDifferencesIn(plan, session, asks_for_frames);
}

PlanCheck RecordOrCheckPlan(const Plan& plan, const std::string& session, SessionCatalog& catalog) {
  const std::string path = session + "/" + kSettingsFile;
  const std::vector<PlanSetting> now = PlanSettings(plan);
  PlanCheck check;
  if (!fs::exists(path)) {
    // A session captured before plans were recorded has frames and no record: its plan is taken
    // as given (said in the catalog), as it always was.
    if (!catalog.Frames().empty())
      catalog.Event("warning", "the session's plan was not recorded (an older acqd): " + plan.path +
                                   " is recorded now as its plan");
    CopyPlanFiles(plan, session);
    WriteSettings(now, path);
    check.first_run = true;
    return check;
  }
  const SettingsComparison c = Compare(now, path);
  if (!c.capture.empty()) {
    throw UserError(plan.path,
                    "differs from the plan session " + session + " was captured with, in " +
                        ListedChanges(c.capture, " that change what is captured"),
                    "resume with the session's own plan (" + session +
                        "/plan.yaml), or give this plan a new output directory");
  }
  check.processing_changes = c.processing;
  for (const std::string& change : check.processing_changes)
    catalog.Event("info", "plan changed for processing: " + change);
  if (!check.processing_changes.empty()) WriteSettings(now, path);
  return check;
}

}  // namespace acq
