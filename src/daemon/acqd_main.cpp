// acqd: runs a capture session from a plan (issue 8).
//
// The plan is loaded and validated completely before anything is opened or moved (every error
// with file:line:column and the fix); `--dry-run` prints the schedule, the collision-checked
// visiting order and the estimated time. A run opens the control socket, the backend (for sim:
// re-executed into the simulated instrument's environment), the gantry and the camera, verifies
// the session catalog (resuming what a killed run left), homes, and runs the capture steps
// (capture.h: the calibration boards, the sample, validation, Spectralon). It then processes the
// session (process.h: calibration, HDR, correspondence, reconstruction, validation), for the
// simulated instrument scores the map and the calibration against the ground truth, and writes
// the report (report.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "acq/map_score.h"
#include "acq/move_planner.h"
#include "acq/plan.h"
#include "acq/plan_checks.h"
#include "acq/plan_record.h"
#include "brdf/basis_file.h"
#include "brdf/directions.h"
#include "brdf/evaluation.h"
#include "calib/camera_model.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/seconds_since.h"
#include "core/stop_request.h"
#include "daemon/control.h"
#include "daemon/sim_world.h"
#include "hw/aravis_camera.h"
#include "hw/protocol_gantry.h"
#include "hw/replay_camera.h"
#include "hw/replay_gantry.h"
#include "hw/usb_transport.h"
#include "io/float_planes_exr.h"
#include "io/session_catalog.h"
#include "io/session_lock.h"
#include "session/background.h"
#include "session/capture.h"
#include "session/process.h"
#include "session/report.h"

namespace acq {
namespace {

constexpr const char* kUsage =
    "usage: acqd --session PLAN.yaml [--dry-run] [--socket PATH]\n"
    "  --dry-run   validate the plan, print the schedule, the visiting order and the estimated\n"
    "              time; open no device, move nothing\n"
    "  --socket    the control socket acqctl talks to (default $XDG_RUNTIME_DIR/acqd.sock)\n";

// Per frame, beyond its exposure: trigger, readout and transfer of a frame over GigE Vision
// (measured: 0.06 s for 2048 x 2048 Mono16 on loopback; a real link is slower) plus the
// exposure change. An estimate for planning, not a promise.
constexpr double kFrameOverheadS = 0.15;

// The simulated session's map against the card's true materials (as the mono camera records
// them), and the homogeneous result for the same materials at the same directions.
void ScoreAgainstTruth(const Plan& plan, const SimWorld& world, SessionReport* report) {
  const MappedBasis mapped = MappedBasis::Open(plan.basis_file);
  const std::vector<MerlBrdf> truth = world.TruthTables();
  report->score = ScoreMap(ReadSvbrdfMap(plan.output + "/svbrdf.exr"), mapped.View(),
                           world.LabelsAt(report->process.sample_points), truth);
  FloatPlanes error;  // per pixel, for a look at where the map is wrong
  error.width = report->process.reference_width;
  error.height = report->process.reference_height;
  error.planes["log_rmse"] = report->score.log_rmse;
  error.attributes["meaning"] = "log-space RMSE against the true material; -1 off the card";
  WriteFloatPlanesExr(plan.output + "/ground_truth/error.exr", error);
  std::vector<double> homogeneous;
  const std::vector<std::size_t> bins = BinsOf(plan.directions);
  for (const MerlBrdf& m : truth) {
    double sum = 0;
    for (const ChannelError& e :
         EvaluateHomogeneous(mapped.View(), m, bins, RidgeOptions{plan.components, plan.eta})) {
      homogeneous.push_back(e.log_rmse);
      sum += e.log_rmse / 3;
    }
    report->homogeneous_log_rmse.push_back(sum);
  }
  for (const std::string& path : plan.sim_materials)
    report->materials.push_back(std::filesystem::path(path).stem().string());
  report->homogeneous_median_log_rmse = Median(homogeneous);
  report->scored = true;
}

// The calibrated geometry against the simulated instrument's: points on a grid over the sample
// projected through the calibrated camera and pose, and through the true ones at the arms the
// gantry measured, at every board pose; and the camera centre the board alone would give.
void ScoreCalibration(const Plan& plan, const SimWorld& world, SessionReport* report) {
  const SessionCalibration& c = report->process.calibration;
  std::vector<double> misalignment, eye_error_deg;
  for (const BoardPoseResult& b : c.boards) {
    if (!b.found) continue;
    const calib::Pose truth =
        sim::ViewFromArms(b.arms, plan.camera_distance_mm, plan.light_distance_mm, 1)
            .cam_from_sample;
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j) {
        const Eigen::Vector3d p((i / 4.0 - 0.5) * plan.sample_width_mm,
                                (j / 4.0 - 0.5) * plan.sample_height_mm, 0);
        const Eigen::Vector2d a = c.camera.Project(b.cam_from_sample * p);
        const Eigen::Vector2d t = world.camera_model().Project(truth * p);
        misalignment.push_back((a - t).norm());
      }
    // The camera's centre the board alone gives, as seen from the sample centre.
    const Eigen::Vector3d eye = b.cam_from_sample.Inverse().t, true_eye = truth.Inverse().t;
    eye_error_deg.push_back(
        RadToDeg(std::acos(std::min(1.0, eye.normalized().dot(true_eye.normalized())))));
  }
  if (misalignment.empty()) return;
  report->alignment_median_px = Median(misalignment);
  report->alignment_max_px = *std::max_element(misalignment.begin(), misalignment.end());
  report->board_eye_error_median_deg = Median(eye_error_deg);
  report->board_eye_error_max_deg = *std::max_element(eye_error_deg.begin(), eye_error_deg.end());
}

// The calibration inputs the run will read, read now: the lens model's name (mrcal knows it)
// and a camera model calibrated before.
void CheckCalibrationInputs(const Plan& plan) {
  calib::ParseLensModel(plan.lensmodel, plan.lensmodel_where);
  if (plan.intrinsics_file.empty()) return;
  try {
    calib::CameraModel::Read(plan.intrinsics_file);
  } catch (const UserError& e) {
    throw UserError(plan.path + ": calibration.camera_model", e.what(),
                    "give a .cameramodel written by acqd or `acq calibrate intrinsics`");
  }
}

void PrintDryRun(const Plan& plan) {
  std::printf("plan %s: backend %s, session directory %s\n", plan.path.c_str(),
              BackendName(plan.backend), plan.output.c_str());
  std::printf("sample %.0f x %.0f mm; %zu directions from %s; basis %s (k = %d)\n\n",
              plan.sample_width_mm, plan.sample_height_mm, plan.directions.size(),
              plan.directions_file.c_str(), plan.basis_file.c_str(), plan.components);
  const SessionVisits visits = PlanVisits(plan);
  const VisitPlan& visit = visits.sample;
  const VisitPlan naive = PlanInFileOrder(plan.directions, plan.motion);
  std::printf("visiting order (collision-checked, from home):\n");
  std::printf("%4s  %-36s %9s %9s %9s %9s %8s\n", "step", "direction", "light_th", "light_ph",
              "cam_th", "cam_ph", "move_s");
  for (std::size_t i = 0; i < visit.poses.size(); ++i) {
    const PlannedPose& p = visit.poses[i];
    std::printf("%4zu  %-36s %9.2f %9.2f %9.2f %9.2f %8.2f\n", i + 1,
                plan.directions[p.index].where.c_str(), RadToDeg(p.arms.light_theta),
                RadToDeg(p.arms.light_phi), RadToDeg(p.arms.camera_theta),
                RadToDeg(p.arms.camera_phi), p.move_s);
  }
  // Per pose: the bracket's exposures and each frame's overhead; an automatic choice adds two
  // probe frames (a 5-frame bracket of 2-stop steps from ~1 ms is about 0.35 s of exposure).
  double bracket_s = 0;
  for (double t : plan.bracket_us) bracket_s += t / 1e6;
  const std::size_t bracket = plan.auto_bracket ? 5 : plan.bracket_us.size();
  if (plan.auto_bracket) bracket_s = 0.35;
  std::printf("\nschedule (an operator prompt before each new item; `acqctl confirm`):\n");
  std::printf("  home the gantry\n");
  double total_s = 0;
  for (const CaptureStep& step : CaptureSteps(plan, visits)) {
    const bool board = step.max_auto_frames > 0;
    const std::size_t poses = step.visit->poses.size();
    const std::size_t frames = board ? 1 : bracket;
    const int probes = board || plan.auto_bracket ? 2 : 0;
    const double frames_s =
        double(poses) * ((board ? 0.03 : bracket_s) + double(frames + probes) * kFrameOverheadS);
    std::printf(
        "  %-22s %3zu poses x %zu frame%s, %-32s motion %6.1f s, frames %6.1f s\n",
        step.step.c_str(), poses, frames, frames > 1 ? "s" : " ",
        (step.item + (step.new_placement_per_pose ? " (placed anew each pose)" : "")).c_str(),
        step.visit->total_s, frames_s);
    total_s += step.visit->total_s + frames_s;
  }
  std::printf(
      "  processing: HDR merge, calibration (intrinsics, cam_from_sample per pose), "
      "correspondence, reconstruction, validation renders, report\n");
  std::printf(
      "\nestimated capture time, without the operator: %.1f s (the sample's %zu poses take "
      "%.1f s of motion a pass in this order, %.1f s in file order)\n",
      total_s, visit.poses.size(), visit.total_s, naive.total_s);
}

int Run(int argc, char** argv) {
  std::string session, socket = DefaultControlSocket();
  bool dry_run = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--session") && i + 1 < argc)
      session = argv[++i];
    else if (!std::strcmp(argv[i], "--socket") && i + 1 < argc)
      socket = argv[++i];
    else if (!std::strcmp(argv[i], "--dry-run"))
      dry_run = true;
    else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::fputs(kUsage, stdout);
      return 0;
    } else {
      std::fprintf(stderr, "acqd: unknown argument '%s'\n%s", argv[i], kUsage);
      return 1;
    }
  }
  if (session.empty()) {
    std::fputs(kUsage, stderr);
    return 1;
  }
  const Plan plan = LoadPlan(session);
  CheckPlanResources(plan);  // what the run will open: the basis, the output folder
  CheckCalibrationInputs(plan);
  if (dry_run) {
    PrintDryRun(plan);
    return 0;
  }
  // The simulated instrument lives in this process, in its own network namespace, under
  // umockdev: re-execute into that environment first.
  if (plan.backend == Backend::kSim && !SimEnvironmentReady())
    throw UserError("acqd", ReexecForSim(argc, argv),
                    "the sim backend needs unshare (util-linux), ip (iproute2) and umockdev");
  InstallStopHandlers();
  // The session is this process's from here to its end: a second acqd (or a repair) is refused.
  const SessionLock lock(plan.output, "acqd");
  if (!lock.taken_over_from().empty())
    std::printf("taking over the session's lock from %s, which is no longer running\n",
                lock.taken_over_from().c_str());
  const auto session_start = SteadyClock::now();
  SessionReport report;
  report.plan = plan.path;
  report.backend = BackendName(plan.backend);
  report.session = plan.output;
  // The control socket first, so that `acqctl status` shows every phase of the start.
  ControlServer control(socket);
  SessionStatus status;
  auto phase = [&](const std::string& what) {
    status.step = what;
    control.Publish(status);
    std::printf("%s\n", what.c_str());
    std::fflush(stdout);
  };
  std::unique_ptr<SimWorld> world;
  UsbDeviceId usb = plan.usb;
  AravisCameraOptions camera_options;
  camera_options.id = plan.camera_id;
  if (plan.backend == Backend::kSim) {
    phase("building the simulated instrument");
    world = std::make_unique<SimWorld>(plan);
    usb = world->usb_id();
    camera_options.id = world->camera_address();
  }
  // The session's record before any device: a resume with another plan is refused here, and
  // nothing is deleted before the catalog is known to match the frames.
  phase("verifying the session in " + plan.output);
  SessionCatalog catalog(plan.output);
  if (!lock.taken_over_from().empty())
    catalog.Event("warning", "lock taken over from " + lock.taken_over_from());
  const PlanCheck plan_check = RecordOrCheckPlan(plan, plan.output, catalog);
  for (const std::string& change : plan_check.processing_changes)
    std::printf("plan changed for processing only (allowed, recorded): %s\n", change.c_str());
  const SessionCatalog::Repair repair = catalog.VerifyAndRepair();
  if (repair.verified > 0 || !repair.orphans.empty() || !repair.bad.empty())
    std::printf("resuming %s: %d frames verified, %zu damaged and %zu unrecorded frames dropped\n",
                plan.output.c_str(), repair.verified, repair.bad.size(), repair.orphans.size());
  if (!repair.unknown.empty())
    std::printf("left alone in %s/frames: %zu files acqd did not write (%s%s)\n",
                plan.output.c_str(), repair.unknown.size(), repair.unknown.front().c_str(),
                repair.unknown.size() > 1 ? ", ..." : "");
  // Devices are opened before anything moves: an absent or wrong one ends here. Replay: the
  // recorded session's frames and arm angles stand in for both.
  std::unique_ptr<UsbTransport> transport;
  std::unique_ptr<Gantry> gantry_device;
  std::unique_ptr<Camera> camera_device;
  ReplayCamera* replay = nullptr;
  if (plan.backend == Backend::kReplay) {
    phase("opening the recorded session " + plan.replay_session);
    auto replay_camera = std::make_unique<ReplayCamera>(plan.replay_session);
    replay = replay_camera.get();
    gantry_device = std::make_unique<ReplayGantry>(replay_camera->files());
    camera_device = std::move(replay_camera);
  } else {
    phase("opening the gantry (" + usb.Describe() + ")");
    transport = std::make_unique<UsbTransport>(usb);
    gantry_device = std::make_unique<ProtocolGantry>(*transport);
    phase("opening the camera (" + camera_options.id + ")");
    camera_device = std::make_unique<AravisCamera>(camera_options);
  }
  Gantry& gantry = *gantry_device;
  Camera& camera = *camera_device;
  if (replay) {
    // The recorded decisions (automatic exposures) are the replay's: no probe frames to serve.
    const SessionCatalog recorded(plan.replay_session);
    for (const auto& [key, value] : recorded.Decisions())
      if (catalog.Decision(key).empty()) catalog.RecordDecision(key, value);
    // A resumed replay has taken the first frames of the recording, in its order.
    replay->Skip(std::size_t(repair.verified));
  }
  // From here on a failure is the session's: recorded in its catalog and shown by acqctl as the
  // last error before acqd exits (the frames taken stay; running the plan again resumes).
  try {
    if (world) world->WriteGroundTruth(plan.output + "/ground_truth");
    WriteDirectionsTsv(plan.directions, plan.output + "/directions.tsv",
                       "the directions this session used: " + plan.directions_file);
    catalog.Event("info", "session started (" + std::string(BackendName(plan.backend)) + ")");
    phase("homing");
    HomeAndWait(gantry, HomingTimeoutSeconds(plan.motion.SlowestAxis(), plan.motion.settle_s));
    phase("planning the visiting order");
    auto planning_start = SteadyClock::now();
    const SessionVisits visits = PlanVisits(plan);
    report.planning_s = SecondsSince(planning_start);
    const std::vector<CaptureStep> steps = CaptureSteps(plan, visits);
    CaptureContext context{gantry,  camera,
                           catalog, control,
                           status,  replay ? "replay of " + plan.replay_session : usb.Describe()};
    if (world) {
      context.ask_operator = plan.sim_operator;
      context.place = [&](const std::string& item) { world->Place(item); };
    }
    if (replay) {
      context.ask_operator = false;  // the recorded frames hold whatever was placed
      context.place = [](const std::string&) {};
    }
    // Processing that overlaps the capture: merges of finished poses, the calibration once the
    // boards are in.
    BackgroundProcessing background(plan);
    const std::string last_board_step = plan.validation.empty() ? "board" : "board_validation";
    context.pose_captured = [&](const std::string& step, int pose) {
      background.PoseCaptured(catalog.directory(), step, pose, catalog.FramesOf(step, pose));
    };
    context.step_captured = [&](const std::string& step) {
      if (step == last_board_step) background.BoardsCaptured(SessionFrames::Of(catalog));
    };
    for (const CaptureStep& step : steps) context.poses_total += int(step.visit->poses.size());
    for (const CaptureStep& step : steps) report.capture += Capture(plan, step, context);
    gantry.SetLight(false, 0);
    const CaptureReport& r = report.capture;
    catalog.Event("info", "captured: " + std::to_string(r.frames_taken) + " frames taken, " +
                              std::to_string(r.frames_skipped) + " already there");
    std::printf(
        "captured into %s: %d frames taken, %d already there (motion %.1f s, exposure %.1f s, "
        "transfer %.1f s)\n",
        plan.output.c_str(), r.frames_taken, r.frames_skipped, r.motion_s, r.exposure_s,
        r.transfer_s);
    // Without Spectralon captures the light's intensity must be known: the simulated world's
    // (the plan refuses a real instrument without them).
    const double light = world ? world->LightIntensityInCounts(plan.camera.pixel_format) : 0;
    if (world && catalog.Decision(kLightIntensityDecision).empty()) {
      char text[40];  // recorded for `acq process`, which has no simulated world to ask
      std::snprintf(text, sizeof text, "%.17g", light);
      catalog.RecordDecision(kLightIntensityDecision, text);
    }
    ThrowIfStopRequested();
    phase("processing: finishing what ran during the capture");
    const auto finishing_start = SteadyClock::now();
    std::optional<SessionCalibration> calibrated = background.Finish();
    report.background_wait_s = SecondsSince(finishing_start);
    report.background_busy_s = background.busy_s();
    report.background_poses = background.poses_merged();
    ThrowIfStopRequested();
    phase("processing: HDR merge, calibration, correspondence, reconstruction, validation");
    report.process = ProcessSession(plan, catalog, {light}, std::move(calibrated));
    if (world) {
      phase("scoring against the simulated card's ground truth");
      const auto scoring_start = SteadyClock::now();
      ScoreAgainstTruth(plan, *world, &report);
      ScoreCalibration(plan, *world, &report);
      report.scoring_s = SecondsSince(scoring_start);
    }
    report.wall_s = SecondsSince(session_start);
    WriteReport(report, plan.output);
    std::printf("\n%s\nreport: %s/report.txt and report.json\n", report.Text().c_str(),
                plan.output.c_str());
  } catch (const Stopped& e) {
    // Asked to stop: the arms stopped (again: harmless when a move's wait did it), the stop
    // recorded and published; the socket goes with the server, the lock with the process.
    try {
      gantry.Stop();
    } catch (const std::exception&) {  // a gantry already gone: the stop is still recorded
    }
    status.state = DaemonState::kStopped;
    status.last_error = e.what();
    control.Publish(status);
    catalog.Event("warning", e.what());
    throw;
  } catch (const std::exception& e) {
    if (status.state != DaemonState::kAborted) status.state = DaemonState::kFailed;
    status.last_error = e.what();
    control.Publish(status);
    catalog.Event("error", e.what());
    throw;
  }
  status.state = DaemonState::kDone;
  status.progress = 1;
  phase("done");
  return 0;
}

}  // namespace
}  // namespace acq

int main(int argc, char** argv) {
  try {
    return acq::Run(argc, argv);
  } catch (const acq::Stopped& e) {
    std::fprintf(stderr, "acqd: %s\n", e.what());
    return 128 + e.signal_number();  // the shell's convention for "ended by this signal"
  } catch (const acq::UserError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {  // a library's: still a message, never a crash
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
