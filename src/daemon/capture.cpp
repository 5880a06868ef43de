#include "daemon/capture.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "core/angles.h"
#include "core/error.h"
#include "hw/frame_file.h"

namespace acq {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string Degrees(const ArmAngles& a) {
  char s[96];
  std::snprintf(s, sizeof s, "%.3f %.3f %.3f %.3f", RadToDeg(a.light_theta), RadToDeg(a.light_phi),
                RadToDeg(a.camera_theta), RadToDeg(a.camera_phi));
  return s;
}

// Stops the gantry and ends the session here, resumable.
[[noreturn]] void Abort(ControlServer& control, SessionStatus& status, Gantry& gantry) {
  gantry.Stop();
  const std::string where = status.state == "paused" ? "while paused at " : "at ";
  status.state = "aborted";
  control.Publish(status);
  throw UserError("acqd", "aborted by the operator " + where + status.step,
                  "the gantry is stopped; run acqd again with the same plan to resume");
}

// At a safe point: publish, then honour pause (wait for resume) and abort (stop, throw).
void SafePoint(ControlServer& control, SessionStatus& status, Gantry& gantry) {
  control.Publish(status);
  for (std::string c = control.TakeCommand(); !c.empty(); c = control.TakeCommand()) {
    if (c == "abort") Abort(control, status, gantry);
    if (c != "pause") continue;
    const std::string was = status.state;
    status.state = "paused";
    control.Publish(status);
    for (std::string next = control.TakeCommand(); next != "resume"; next = control.TakeCommand()) {
      if (next == "abort") Abort(control, status, gantry);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    status.state = was;
    control.Publish(status);
  }
}

}  // namespace

CaptureReport CaptureSample(const Plan& plan, const VisitPlan& visit, Gantry& gantry,
                            Camera& camera, SessionCatalog& catalog, ControlServer& control) {
  namespace fs = std::filesystem;
  CaptureReport report;
  SessionStatus status;
  status.state = "running";
  const std::size_t per_pose = plan.bracket_us.size();
  const std::size_t total = visit.poses.size() * per_pose;
  const TrapezoidProfile slowest =
      plan.motion.theta.speed < plan.motion.phi.speed ? plan.motion.theta : plan.motion.phi;
  for (std::size_t i = 0; i < visit.poses.size(); ++i) {
    const PlannedPose& pose = visit.poses[i];
    bool all_done = true;
    for (double t : plan.bracket_us) all_done = all_done && catalog.HasFrame("sample", int(i), t);
    if (all_done) {
      report.frames_skipped += int(per_pose);
      continue;
    }
    status.step = "sample pose " + std::to_string(i + 1) + " of " +
                  std::to_string(visit.poses.size()) + ": moving";
    SafePoint(control, status, gantry);
    const auto move_start = Clock::now();
    MoveAndWait(gantry, pose.arms, slowest, plan.motion.settle_s);
    report.motion_s += Since(move_start);
    const GantryStatus arrived = gantry.Status();
    const ArmAngles& m = arrived.measured;
    const double arms[4] = {m.light_theta, m.light_phi, m.camera_theta, m.camera_phi};
    for (int a = 0; a < 4; ++a) status.arms_deg[a] = RadToDeg(arms[a]);
    for (std::size_t e = 0; e < per_pose; ++e) {
      const double t = plan.bracket_us[e];
      if (catalog.HasFrame("sample", int(i), t)) {
        ++report.frames_skipped;
        continue;
      }
      status.step = "sample pose " + std::to_string(i + 1) + " of " +
                    std::to_string(visit.poses.size()) + ", exposure " + std::to_string(e + 1) +
                    " of " + std::to_string(per_pose);
      SafePoint(control, status, gantry);
      CameraSettings settings = plan.camera;
      settings.exposure_us = t;
      camera.Apply(settings);
      const auto grab_start = Clock::now();
      const Frame frame = camera.Grab();
      const double grab_s = Since(grab_start);
      report.exposure_s += t / 1e6;
      report.transfer_s += std::max(0.0, grab_s - t / 1e6);
      char name[64];
      std::snprintf(name, sizeof name, "frames/%03zu_sample_%.0fus.exr", i, t);
      WriteFrameExr((fs::path(catalog.directory()) / name).string(), frame,
                    {{"step", "sample"},
                     {"pose", std::to_string(i)},
                     {"direction", plan.directions[pose.index].where},
                     {"arms_commanded_deg", Degrees(pose.arms)},
                     {"arms_measured_deg", Degrees(arrived.measured)},
                     {"camera", camera.Describe()}});
      catalog.RecordFrame({"sample", int(i), t, name, "", 0});
      ++report.frames_taken;
      const StreamStatistics stats = camera.Statistics();
      status.frames = report.frames_taken + report.frames_skipped;
      status.incomplete_frames = long(stats.incomplete);
      status.progress = double(status.frames) / double(total);
    }
  }
  catalog.MarkStepDone("sample");
  status.state = "done";
  status.step = "sample captured";
  status.progress = 1;
  control.Publish(status);
  return report;
}

}  // namespace acq
