#include "session/capture.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "acq/hdr.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/rusinkiewicz.h"
#include "core/seconds_since.h"
#include "core/stop_request.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"
#include "session/frame_preview.h"

namespace acq {
namespace {

// Stops the gantry and ends the session here, resumable.
[[noreturn]] void Abort(CaptureContext& c) {
  c.gantry.Stop();
  const std::string where = c.status.state == DaemonState::kPaused ? "while paused at "
                            : c.status.state == DaemonState::kWaiting
                                ? "while waiting for the operator after "
                                : "at ";
  c.status.state = DaemonState::kAborted;
  c.status.prompt.clear();
  c.status.prompt_id = 0;
  c.control.Publish(c.status);
  throw UserError("acqd", "aborted by the operator " + where + c.status.step,
                  "the gantry is stopped; run acqd again with the same plan to resume");
}

// Waits for `wanted` (resume; confirm of prompt `prompt_id`), honouring abort and a stop
// signal meanwhile. A confirm of another prompt (one that raced with the prompt's end) is
// dropped.
void WaitFor(CaptureContext& c, CommandKind wanted, int prompt_id = 0) {
  for (;;) {
    ThrowIfStopRequested();
    const std::optional<ControlCommand> next = c.control.TakeCommand();
    if (next && next->kind == CommandKind::kAbort) Abort(c);
    if (next && next->kind == wanted && next->prompt_id == prompt_id) return;
    if (!next) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

// At a safe point: publish, then honour a stop signal, pause (wait for resume) and abort
// (stop, throw).
void SafePoint(CaptureContext& c) {
  c.control.Publish(c.status);
  ThrowIfStopRequested();
  for (std::optional<ControlCommand> command = c.control.TakeCommand(); command;
       command = c.control.TakeCommand()) {
    if (command->kind == CommandKind::kAbort) Abort(c);
    if (command->kind != CommandKind::kPause) continue;
    const DaemonState was = c.status.state;
    c.status.state = DaemonState::kPaused;
    c.control.Publish(c.status);
    WaitFor(c, CommandKind::kResume);
    c.status.state = was;
    c.control.Publish(c.status);
  }
}

std::string Instructions(const Placement& p, int intrinsics_captures) {
  switch (p.item) {
    case Item::kSpectralon:
      return "place the Spectralon board flat on the sample plane, centred where the sample was";
    case Item::kBoard:
      if (p.held_pose == 0)
        return "lay the chessboard flat on the sample plane, centred, its x axis towards gantry "
               "azimuth 0 (it defines the sample frame)";
      return "hold or prop the chessboard in pose " + std::to_string(p.held_pose) + " of " +
             std::to_string(intrinsics_captures) +
             " under the camera: all of it in view, tilted 20 to 40 degrees, a different part "
             "of the image and a different tilt each time";
    case Item::kChart:
      return "place the colour chart (ColorChecker Classic) flat on the sample plane, centred, "
             "its dark skin patch at the corner towards gantry azimuth 180 and 270, the grey row "
             "towards 90";
    case Item::kSample:
      break;
  }
  return "place the sample flat on the sample plane, centred under the reference view";
}

// Makes sure `item` lies under the gantry: an operator is asked and confirms with `acqctl
// confirm` (the gantry holds still meanwhile), or the simulated instrument places it.
double Place(CaptureContext& c, const Placement& item, int intrinsics_captures) {
  if (c.placed == item) return 0;
  const auto start = SteadyClock::now();
  if (c.ask_operator) {
    const DaemonState was = c.status.state;
    c.status.state = DaemonState::kWaiting;
    c.status.prompt = Instructions(item, intrinsics_captures) + ", then run `acqctl confirm`";
    c.status.prompt_id = ++c.prompts_shown;
    c.control.Publish(c.status);
    std::printf("operator (prompt %d): %s\n", c.status.prompt_id, c.status.prompt.c_str());
    std::fflush(stdout);
    WaitFor(c, CommandKind::kConfirm, c.status.prompt_id);
    c.status.prompt.clear();
    c.status.prompt_id = 0;
    c.status.state = was;
    c.control.Publish(c.status);
  }
  if (c.place) c.place(item);
  c.placed = item;
  c.catalog.Event("info", ToString(item) + " placed");
  return SecondsSince(start);
}

// The camera's stream statistics so far, as recorded with each frame.
std::string StreamAttribute(const StreamStatistics& s) {
  char text[200];
  std::snprintf(text, sizeof text,
                "completed %llu incomplete %llu missing_packets %llu resent_packets %llu "
                "retakes %llu reopens %llu",
                (unsigned long long)s.completed, (unsigned long long)s.incomplete,
                (unsigned long long)s.missing_packets, (unsigned long long)s.resent_packets,
                (unsigned long long)s.retakes, (unsigned long long)s.reopens);
  return text;
}

std::vector<double> RecordedBracket(const Plan& plan, const CaptureStep& step, int pose,
                                    const SessionCatalog& catalog) {
  if (!plan.camera.auto_bracket && step.max_auto_frames == 0) return plan.camera.bracket_us;
  return ParseBracketText(catalog.Decision(BracketDecisionKey(step.step, pose)));
}

// Frames the driver had to take again (the camera's retake count went from `before` to
// `after`) are whole, but the operator should know which (a network or a machine that drops
// packets; each frame's `stream` attribute has the counts): a warning in the session's events
// naming `what`.
void NoteRetakes(CaptureContext& c, std::uint64_t before, std::uint64_t after,
                 const std::string& what) {
  if (after > before)
    c.catalog.Event("warning", what + ": taken " + std::to_string(after - before) +
                                   " more time(s), the camera's frame having arrived incomplete");
}

// The automatic bracket chosen at the pose the gantry holds, recorded so that a resumed run
// takes the same exposures; returned as the catalog gives it back (what a resumed run reads).
std::vector<double> ChooseAndRecordBracket(const Plan& plan, const CaptureStep& step, int pose,
                                           CaptureContext& c, CaptureReport* report) {
  const auto start = SteadyClock::now();
  AutoBracketOptions options;
  if (step.max_auto_frames > 0) options.max_frames = step.max_auto_frames;
  const std::uint64_t retakes_before = c.camera.Statistics().retakes;
  const std::vector<double> exposures =
      ChooseBracket(c.camera, plan.camera.settings, HdrOptions{}, options);
  NoteRetakes(c, retakes_before, c.camera.Statistics().retakes,
              std::string(ToString(step.step)) + " pose " + std::to_string(pose) +
                  ", metering its bracket");
  report->bracket_probe_s += SecondsSince(start);
  c.catalog.RecordDecision(BracketDecisionKey(step.step, pose), BracketText(exposures));
  return RecordedBracket(plan, step, pose, c.catalog);
}

}  // namespace

CaptureReport& CaptureReport::operator+=(const CaptureReport& o) {
  frames_taken += o.frames_taken;
  frames_skipped += o.frames_skipped;
  motion_s += o.motion_s;
  exposure_s += o.exposure_s;
  transfer_s += o.transfer_s;
  bracket_probe_s += o.bracket_probe_s;
  settings_s += o.settings_s;
  operator_s += o.operator_s;
  return *this;
}

std::vector<Direction> IntrinsicsDirection() {
  const Eigen::Vector3d light = SphericalDirection(DegToRad(30), 0), camera(0, 0, 1);
  RusinkiewiczAngles angles = RusinkiewiczFromDirections(light, camera);
  angles.phi_h = 0;  // free (Direction's convention): the planner chooses the azimuth
  return {{angles, "the intrinsics pose (camera straight above the sample, light 30 deg from it)"}};
}

SessionVisits PlanVisits(const Plan& plan) {
  SessionVisits v;
  v.sample = PlanShortest(plan.directions, plan.gantry.motion);
  if (plan.camera.ChartCaptured() && !v.sample.poses.empty()) {
    v.chart.poses.push_back(v.sample.poses.front());
    v.chart.total_s = v.chart.poses.front().move_s;
  }
  // Only the sample's directions reconstruct: the others are visited the fastest way.
  GantryMotion fastest = plan.gantry.motion;
  fastest.half_vector_azimuths = HalfVectorAzimuths::kFastest;
  if (!plan.validation.empty()) v.validation = PlanShortest(plan.validation, fastest);
  if (plan.calibration.intrinsics_captures > 0) {
    // The one pose, held for every capture (the moves after the first are empty).
    const VisitPlan once = PlanShortest(v.intrinsics_direction, fastest);
    v.intrinsics = once;
    for (int i = 1; i < plan.calibration.intrinsics_captures; ++i) {
      v.intrinsics.poses.push_back(once.poses.front());
      v.intrinsics.poses.back().move_s = 0;
    }
  }
  return v;
}

std::vector<CaptureStep> CaptureSteps(const Plan& plan, const SessionVisits& visits) {
  std::vector<CaptureStep> steps;
  const bool validate = !plan.validation.empty();
  // A board needs one frame, its white squares just short of saturation: exposed for at the
  // pose whatever the plan's bracket (a grazing light leaves it too dark for a fixed one).
  if (plan.calibration.intrinsics_captures > 0)
    steps.push_back({Step::kIntrinsics, &visits.intrinsics, &visits.intrinsics_direction, true, 1});
  steps.push_back({Step::kBoard, &visits.sample, &plan.directions, false, 1});
  if (validate)
    steps.push_back({Step::kBoardValidation, &visits.validation, &plan.validation, false, 1});
  steps.push_back({Step::kSample, &visits.sample, &plan.directions});
  if (validate) steps.push_back({Step::kValidation, &visits.validation, &plan.validation});
  if (plan.spectralon) {
    steps.push_back({Step::kSpectralon, &visits.sample, &plan.directions});
    if (validate)
      steps.push_back({Step::kSpectralonValidation, &visits.validation, &plan.validation});
  }
  // The chart at the sample's first pose, where the Spectralon and the board were too.
  if (plan.camera.ChartCaptured()) steps.push_back({Step::kChart, &visits.chart, &plan.directions});
  return steps;
}

namespace {

// A pose the gantry holds: where it was commanded and where it arrived.
struct HeldPose {
  const PlannedPose& planned;
  std::size_t index;  // in the step's visiting order
  GantryStatus arrived;
};

// Takes one exposure of the bracket at the pose the gantry holds: the frame written atomically
// into the session with its metadata, then recorded in the catalog.
void TakeFrame(const Plan& plan, const CaptureStep& step, const HeldPose& pose, double t,
               const std::vector<double>& bracket, CaptureContext& c, CaptureReport* report) {
  CameraSettings settings = plan.camera.settings;
  settings.exposure_us = t;
  const auto apply_start = SteadyClock::now();
  c.camera.Apply(settings);
  report->settings_s += SecondsSince(apply_start);
  const std::uint64_t retakes_before = c.camera.Statistics().retakes;
  const auto grab_start = SteadyClock::now();
  Frame frame = c.camera.Grab();
  const double grab_s = SecondsSince(grab_start);
  // The grab's wall time split into the exposure and the rest (trigger, readout, transfer). A
  // simulated camera renders at once, whatever the exposure: there the grab can be shorter than
  // the exposure, and only the time spent is counted.
  const double exposing_s = std::min(grab_s, t / 1e6);
  report->exposure_s += exposing_s;
  report->transfer_s += grab_s - exposing_s;
  // The live view's copy (a few thousand pixels' work) before the frame goes to the writer.
  FramePreview preview = PreviewOf(frame);
  preview.step = c.status.step;
  c.control.PublishFrame(preview);
  const int i = int(pose.index);
  const std::string name = FrameFileName(step.step, i, t);
  const StreamStatistics stats = c.camera.Statistics();
  NoteRetakes(c, retakes_before, stats.retakes, name);
  // Written and recorded by the writer while the gantry moves on (frame_writer.h).
  c.writer.Write(std::move(frame),
                 {{"step", ToString(step.step)},
                  {"pose", std::to_string(i)},
                  {"direction", (*step.directions)[pose.planned.index].where},
                  {"arms_commanded_deg", ArmAnglesAttribute(pose.planned.arms)},
                  {"arms_measured_deg", ArmAnglesAttribute(pose.arrived.measured)},
                  {"camera", c.camera.Describe()},
                  {"gantry", c.gantry_id},
                  {"stream", StreamAttribute(stats)},
                  {"grab_s", std::to_string(grab_s)},
                  {"bracket_us", BracketText(bracket)}},
                 {step.step, i, t, name, "", 0});
  ++report->frames_taken;
  ++c.status.frames;
  c.status.incomplete_frames = long(stats.incomplete);
  c.status.retransmissions = c.gantry.retransmissions();
}

// Places the pose's item, moves there and takes the exposures of `bracket` not in the session
// (chosen now where it is empty, an automatic bracket).
void CapturePose(const Plan& plan, const CaptureStep& step, std::size_t i,
                 std::vector<double> bracket, CaptureContext& c, CaptureReport* report) {
  SessionStatus& status = c.status;
  const std::vector<PlannedPose>& poses = step.visit->poses;
  const std::string where = std::string(ToString(step.step)) + " pose " + std::to_string(i + 1) +
                            " of " + std::to_string(poses.size());
  report->operator_s += Place(c, step.PlacementAt(i), plan.calibration.intrinsics_captures);
  status.step = where + ": moving";
  SafePoint(c);
  const auto move_start = SteadyClock::now();
  MoveAndWait(c.gantry, poses[i].arms, plan.gantry.motion.SlowestAxis(),
              plan.gantry.motion.settle_s);
  report->motion_s += SecondsSince(move_start);
  const HeldPose pose{poses[i], i, c.gantry.Status()};
  const ArmAngles& m = pose.arrived.measured;
  const double arms[4] = {m.light_theta, m.light_phi, m.camera_theta, m.camera_phi};
  for (int a = 0; a < 4; ++a) status.arms_deg[a] = RadToDeg(arms[a]);
  status.step = where + ": choosing the exposures";
  SafePoint(c);
  if (bracket.empty()) bracket = ChooseAndRecordBracket(plan, step, int(i), c, report);
  for (std::size_t e = 0; e < bracket.size(); ++e) {
    if (c.catalog.HasFrame(step.step, int(i), bracket[e])) {
      ++report->frames_skipped;
      ++status.frames;
      continue;
    }
    status.step =
        where + ", exposure " + std::to_string(e + 1) + " of " + std::to_string(bracket.size());
    SafePoint(c);
    TakeFrame(plan, step, pose, bracket[e], bracket, c, report);
  }
}

// A pose the session already has frames of must be the pose those frames were taken at
// (PoseMismatch); the first frame's header is read, not its pixels.
void CheckResumedPose(const CaptureStep& step, std::size_t i, const CaptureContext& c) {
  const std::vector<CatalogFrame> frames = c.catalog.FramesOf(step.step, int(i));
  if (frames.empty()) return;
  const std::string path = c.catalog.directory() + "/" + frames.front().path;
  const std::string why = PoseMismatch(
      step.visit->poses[i], ReadFloatPlanesExr(path, /*read_pixels=*/false).attributes, path);
  if (!why.empty())
    throw UserError(path,
                    "this session's " + std::string(ToString(step.step)) + " pose " +
                        std::to_string(i + 1) + " was taken elsewhere: " + why +
                        " (the poses were planned in another order: another version of acqd?)",
                    "resume it with the acqd that started it, or capture into a new session "
                    "directory; its frames are left as they are");
}

}  // namespace

std::string PoseMismatch(const PlannedPose& planned,
                         const std::map<std::string, std::string>& frame_attributes,
                         const std::string& where) {
  const auto commanded = frame_attributes.find("arms_commanded_deg");
  if (commanded == frame_attributes.end()) return {};  // nothing recorded to compare
  const ArmAngles was = ParseArmAnglesAttribute(commanded->second, where);
  const ArmAngles& is = planned.arms;
  // The attribute keeps a thousandth of a degree.
  const double tolerance = DegToRad(0.002);
  const double d[4] = {was.light_theta - is.light_theta, was.light_phi - is.light_phi,
                       was.camera_theta - is.camera_theta, was.camera_phi - is.camera_phi};
  for (double x : d)
    if (std::abs(x) > tolerance)
      return "its frames' arms " + commanded->second + " deg, this run's " +
             ArmAnglesAttribute(is) + " deg";
  return {};
}

CaptureReport Capture(const Plan& plan, const CaptureStep& step, CaptureContext& c) {
  CaptureReport report;
  SessionStatus& status = c.status;
  status.state = DaemonState::kRunning;
  const std::vector<PlannedPose>& poses = step.visit->poses;
  for (std::size_t i = 0; i < poses.size(); ++i, ++c.poses_done) {
    status.progress = c.poses_total > 0 ? double(c.poses_done) / c.poses_total : 0;
    CheckResumedPose(step, i, c);
    // Empty for an automatic bracket not chosen yet: the pose is not done.
    const std::vector<double> bracket = RecordedBracket(plan, step, int(i), c.catalog);
    bool done = !bracket.empty();
    for (double t : bracket) done = done && c.catalog.HasFrame(step.step, int(i), t);
    if (done) {
      report.frames_skipped += int(bracket.size());
      status.frames += long(bracket.size());
    } else {
      // The capture's ETA from this run's pace over the poses it took (not those it skipped).
      if (c.poses_taken > 0)
        status.eta_s = SecondsSince(c.started) / c.poses_taken * (c.poses_total - c.poses_done);
      ++c.poses_taken;
      CapturePose(plan, step, i, bracket, c, &report);
    }
    if (c.pose_captured)
      c.writer.After([&c, s = step.step, pose = int(i)] { c.pose_captured(s, pose); });
  }
  c.writer.Flush();  // the step's frames all recorded before it is marked done
  c.catalog.MarkStepDone(step.step);
  if (c.step_captured) c.step_captured(step.step);
  status.step = std::string(ToString(step.step)) + " captured";
  c.control.Publish(status);
  return report;
}

}  // namespace acq
