#include "session/run.h"

#include <cstdio>
#include <filesystem>
#include <optional>

#include "acq/move_planner.h"
#include "acq/plan_record.h"
#include "core/error.h"
#include "core/seconds_since.h"
#include "core/stop_request.h"
#include "hw/replay_gantry.h"
#include "io/session_catalog.h"
#include "io/session_lock.h"
#include "session/background.h"
#include "session/capture.h"
#include "session/frame_writer.h"
#include "session/process.h"

namespace acq {
namespace {

using Phase = std::function<void(const std::string&)>;

// The session's record before any device: a resume with another plan is refused here, and
// nothing is deleted before the catalog is known to match the frames.
void VerifySession(const Plan& plan, const SessionLock& lock, SessionCatalog& catalog) {
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
}

// A replay reuses the recording's decisions (its automatic exposures: no probe frames to
// serve) and, resumed, starts after the frames it has taken, in the recording's order.
void PrepareReplay(const Plan& plan, SessionCatalog& catalog, ReplayCamera& replay) {
  const SessionCatalog recorded(plan.replay_session);
  for (const auto& [key, value] : recorded.Decisions())
    if (catalog.Decision(key).empty()) catalog.RecordDecision(key, value);
  replay.Skip(catalog.Frames().size());
}

// Every capture step, with processing that overlaps it: merges of finished poses, the
// calibration once the boards are in, the views' correspondence. Returns what was computed
// meanwhile.
PrecomputedStages CaptureAll(const Plan& plan, SessionDevices& devices, SessionCatalog& catalog,
                             StatusChannel& control, SessionStatus& status, SessionReport* report,
                             const Phase& phase) {
  // The camera takes the plan's settings before anything moves: a pixel format it does not
  // offer is refused here, naming those it does.
  phase(std::string("setting the camera to ") + PixelFormatName(plan.camera.settings.pixel_format));
  devices.camera->Apply(plan.camera.settings);
  phase("homing");
  HomeAndWait(*devices.gantry,
              HomingTimeoutSeconds(plan.gantry.motion.SlowestAxis(), plan.gantry.motion.settle_s));
  phase("planning the visiting order");
  const auto planning_start = SteadyClock::now();
  const SessionVisits visits = PlanVisits(plan);
  report->planning_s = SecondsSince(planning_start);
  const std::vector<CaptureStep> steps = CaptureSteps(plan, visits);
  BackgroundProcessing background(plan);
  // After the worker: destroyed first, it records what it has queued (an abort, a failure)
  // while the worker can still take the poses it completes.
  FrameWriter writer(catalog);
  CaptureContext context{.gantry = *devices.gantry,
                         .camera = *devices.camera,
                         .catalog = catalog,
                         .writer = writer,
                         .control = control,
                         .status = status,
                         .gantry_id = devices.gantry_id,
                         .ask_operator = devices.ask_operator,
                         .place = devices.place};
  const Step last_board_step = plan.validation.empty() ? Step::kBoard : Step::kBoardValidation;
  context.pose_captured = [&](Step step, int pose) {
    background.PoseCaptured(catalog.directory(), step, pose, catalog.FramesOf(step, pose));
  };
  context.step_captured = [&](Step step) {
    if (step == last_board_step) background.BoardsCaptured(SessionFrames::Of(catalog));
  };
  for (const CaptureStep& step : steps) context.poses_total += int(step.visit->poses.size());
  for (const CaptureStep& step : steps) report->capture += Capture(plan, step, context);
  report->writer_busy_s = writer.busy_s();
  report->writer_blocked_s = writer.blocked_s();
  devices.gantry->SetLight(false, 0);
  const StreamStatistics stream = devices.camera->Statistics();
  report->incomplete_frames = long(stream.incomplete);
  report->retaken_frames = long(stream.retakes);
  const CaptureReport& r = report->capture;
  catalog.Event("info", "captured: " + std::to_string(r.frames_taken) + " frames taken, " +
                            std::to_string(r.frames_skipped) + " already there");
  std::printf(
      "captured into %s: %d frames taken, %d already there (motion %.1f s, exposure %.1f s, "
      "transfer %.1f s)\n",
      plan.output.c_str(), r.frames_taken, r.frames_skipped, r.motion_s, r.exposure_s,
      r.transfer_s);
  ThrowIfStopRequested();
  phase("processing: finishing what ran during the capture");
  const auto finishing_start = SteadyClock::now();
  PrecomputedStages computed = background.Finish();
  report->background_wait_s = SecondsSince(finishing_start);
  report->background_busy_s = background.busy_s();
  report->background_poses = background.poses_merged();
  return computed;
}

// The light's intensity where no Spectralon measures it, recorded once for `acq session
// process`, which has no simulated instrument to ask.
void RecordLightIntensity(double light, SessionCatalog& catalog) {
  if (light <= 0 || !catalog.Decision(kLightIntensityDecision).empty()) return;
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", light);
  catalog.RecordDecision(kLightIntensityDecision, text);
}

// The devices' part of the session, from homing to the report.
void CaptureAndProcess(const Plan& plan, const SessionHooks& hooks, SessionDevices& devices,
                       SessionCatalog& catalog, StatusChannel& control, SessionStatus& status,
                       SessionReport* report, const Phase& phase) {
  WriteDirectionsTsv(plan.directions, plan.output + "/directions.tsv",
                     "the directions this session used: " + plan.directions_file);
  catalog.Event("info", "session started (" + std::string(BackendName(plan.backend)) + ")");
  PrecomputedStages computed = CaptureAll(plan, devices, catalog, control, status, report, phase);
  // After CaptureAll, which waited background_wait_s for the overlapped work.
  const auto captured = SteadyClock::now();
  RecordLightIntensity(devices.light_intensity, catalog);
  ThrowIfStopRequested();
  phase("processing: HDR merge, calibration, correspondence, reconstruction, validation");
  report->process = ProcessSession(plan, catalog, {devices.light_intensity}, std::move(computed));
  report->after_capture_s = report->background_wait_s + SecondsSince(captured);
  if (hooks.score) {
    phase("scoring against the ground truth");
    const auto scoring_start = SteadyClock::now();
    hooks.score(report);
    report->scoring_s = SecondsSince(scoring_start);
  }
}

// Records and publishes why the session ended early; the gantry stopped on a stop request.
void RecordFailure(const std::exception& e, bool stopped, Gantry* gantry, SessionCatalog& catalog,
                   StatusChannel& control, SessionStatus& status) {
  if (stopped && gantry) {
    try {
      gantry->Stop();                  // again: harmless when a move's wait did it
    } catch (const std::exception&) {  // a gantry already gone: the stop is still recorded
    }
  }
  if (stopped)
    status.state = DaemonState::kStopped;
  else if (status.state != DaemonState::kAborted)
    status.state = DaemonState::kFailed;
  status.last_error = e.what();
  control.Publish(status);
  catalog.Event(stopped ? "warning" : "error", e.what());
}

}  // namespace

SessionReport RunSession(const Plan& plan, StatusChannel& control, SessionStatus& status,
                         const SessionHooks& hooks) {
  const auto session_start = SteadyClock::now();
  status.session = std::filesystem::absolute(plan.output).string();
  // Each phase in the log with the session's time at its start, so a log says where time went.
  const Phase phase = [&](const std::string& what) {
    status.step = what;
    control.Publish(status);
    std::printf("[%7.1f s] %s\n", SecondsSince(session_start), what.c_str());
    std::fflush(stdout);
  };
  // The session is this run's from here to its end: a second acqd (or a repair) is refused.
  const SessionLock lock(plan.output, "acqd");
  if (!lock.taken_over_from().empty())
    std::printf("taking over the session's lock from %s, which is no longer running\n",
                lock.taken_over_from().c_str());
  phase("verifying the session in " + plan.output);
  SessionCatalog catalog(plan.output);
  VerifySession(plan, lock, catalog);
  SessionReport report;
  report.plan = plan.path;
  report.colour_filter = CfaOf(plan.camera.settings.pixel_format);
  report.backend = BackendName(plan.backend);
  report.session = plan.output;
  SessionDevices devices;
  try {
    devices = hooks.open(phase);
    if (devices.replay) PrepareReplay(plan, catalog, *devices.replay);
    CaptureAndProcess(plan, hooks, devices, catalog, control, status, &report, phase);
    report.wall_s = SecondsSince(session_start);
    WriteReport(report, plan.output);
  } catch (const Stopped& e) {
    RecordFailure(e, true, devices.gantry.get(), catalog, control, status);
    throw;
  } catch (const std::exception& e) {
    RecordFailure(e, false, devices.gantry.get(), catalog, control, status);
    throw;
  }
  std::printf("\n%s\nreport: %s/report.txt and report.json\n", report.Text().c_str(),
              plan.output.c_str());
  status.state = DaemonState::kDone;
  status.progress = 1;
  phase("done");
  return report;
}

SessionDevices OpenReplayDevices(const Plan& plan) {
  SessionDevices d;
  auto camera = std::make_unique<ReplayCamera>(plan.replay_session);
  d.replay = camera.get();
  d.gantry = std::make_unique<ReplayGantry>(camera->files());
  d.camera = std::move(camera);
  d.gantry_id = "replay of " + plan.replay_session;
  d.ask_operator = false;  // the recorded frames hold whatever was placed
  return d;
}

}  // namespace acq
