#include "session/dry_run.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "acq/move_planner.h"
#include "acq/plan_checks.h"
#include "brdf/basis_file.h"
#include "brdf/fov_evaluation.h"
#include "brdf/pixel_solver.h"
#include "calib/camera_model.h"
#include "core/angles.h"
#include "core/error.h"
#include "session/capture.h"

namespace acq {
namespace {

// Per frame, beyond its exposure: trigger, readout and transfer of a frame over GigE Vision
// (measured: 0.06 s for 2048 x 2048 Mono16 on loopback; a real link is slower) plus the
// exposure change. An estimate for planning, not a promise.
constexpr double kFrameOverheadS = 0.15;

void Append(std::string* out, const char* format, ...) {
  char line[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  *out += line;
}

std::string VisitingOrder(const Plan& plan, const VisitPlan& visit) {
  std::string out = "visiting order (collision-checked, from home):\n";
  Append(&out, "%4s  %-36s %9s %9s %9s %9s %8s\n", "step", "direction", "light_th", "light_ph",
         "cam_th", "cam_ph", "move_s");
  for (std::size_t i = 0; i < visit.poses.size(); ++i) {
    const PlannedPose& p = visit.poses[i];
    Append(&out, "%4zu  %-36s %9.2f %9.2f %9.2f %9.2f %8.2f\n", i + 1,
           plan.directions[p.index].where.c_str(), RadToDeg(p.arms.light_theta),
           RadToDeg(p.arms.light_phi), RadToDeg(p.arms.camera_theta), RadToDeg(p.arms.camera_phi),
           p.move_s);
  }
  return out;
}

// The steps with their motion and frame times; adds the estimated total to `*total_s`.
std::string Schedule(const Plan& plan, const SessionVisits& visits, double* total_s) {
  // Per pose: the bracket's exposures and each frame's overhead; an automatic choice adds two
  // probe frames (a 5-frame bracket of 2-stop steps from ~1 ms is about 0.35 s of exposure).
  double bracket_s = 0;
  for (double t : plan.camera.bracket_us) bracket_s += t / 1e6;
  const std::size_t bracket = plan.camera.auto_bracket ? 5 : plan.camera.bracket_us.size();
  if (plan.camera.auto_bracket) bracket_s = 0.35;
  std::string out = "schedule (an operator prompt before each new item; `acqctl confirm`):\n";
  out += "  home the gantry\n";
  for (const CaptureStep& step : CaptureSteps(plan, visits)) {
    const bool board = step.max_auto_frames > 0;
    const std::size_t poses = step.visit->poses.size();
    const std::size_t frames = board ? 1 : bracket;
    const int probes = board || plan.camera.auto_bracket ? 2 : 0;
    const double frames_s =
        double(poses) * ((board ? 0.03 : bracket_s) + double(frames + probes) * kFrameOverheadS);
    const std::string item = ToString(Placement{ItemOf(step.step), 0}) +
                             (step.new_placement_per_pose ? " (placed anew each pose)" : "");
    Append(&out, "  %-22s %3zu poses x %zu frame%s, %-32s motion %6.1f s, frames %6.1f s\n",
           ToString(step.step), poses, frames, frames > 1 ? "s" : " ", item.c_str(),
           step.visit->total_s, frames_s);
    *total_s += step.visit->total_s + frames_s;
  }
  return out;
}

// The plan's directions over its sample (issue 17): the condition number of the rows that each
// of 11 x 11 positions from corner to corner sees, with the arms' distances (the near field), on
// the plan's basis and k; a warning naming the worst position, and what it loses, where the
// reconstruction would mark pixels not valid (PixelSolveOptions::max_condition). The sample is
// taken as a square of its longer side, as the plan's optimiser scores it.
std::string OverTheSample(const Plan& plan) {
  constexpr int kGrid = 11;
  static_assert(kGrid % 2 == 1, "the middle position is the centre");
  const MappedBasis mapped = MappedBasis::Open(plan.reconstruction.basis_file);
  const int k = std::min(plan.reconstruction.components, mapped.View().components);
  const NearFieldGeometry geometry{plan.gantry.camera_distance_mm, plan.gantry.light_distance_mm,
                                   std::max(plan.sample.width_mm, plan.sample.height_mm)};
  const std::vector<PositionCondition> positions =
      ConditionOverSample(mapped.View(), plan.directions, geometry, kGrid, k);
  const PositionCondition& centre = positions[positions.size() / 2];
  const PositionCondition& worst =
      *std::max_element(positions.begin(), positions.end(),
                        [](const PositionCondition& a, const PositionCondition& b) {
                          return a.condition < b.condition;
                        });
  std::string out;
  Append(&out,
         "over the sample (%d x %d positions, corner to corner; k = %d): condition number %.4g "
         "at the centre, worst %.4g at (%.1f, %.1f) mm\n",
         kGrid, kGrid, k, centre.condition, worst.condition, worst.position_mm.x(),
         worst.position_mm.y());
  const double limit = PixelSolveOptions{}.max_condition;
  if (!(worst.condition > limit)) return out;
  std::string lost;
  for (int i : worst.lost) lost += (lost.empty() ? "" : ", ") + plan.directions[i].where;
  Append(&out,
         "warning: at (%.1f, %.1f) mm of the sample the directions' rows are %s (condition "
         "number %.4g, the reconstruction's limit %.0f): its pixels will come out not valid",
         worst.position_mm.x(), worst.position_mm.y(),
         std::isinf(worst.condition) ? "singular" : "poorly conditioned", worst.condition, limit);
  if (!lost.empty()) out += "; it loses " + lost + " (below the horizon or in a masked bin there)";
  out +=
      ".\n  choose the directions for this sample: directions.optimize (scored over the sample), "
      "or `acq directions optimize --sample-size-mm S --fov-objective worst`\n";
  return out;
}

// How far the plan's half vectors leave a relief's facets from a highlight, and the remedy
// where normals are estimated from the fastest azimuths.
std::string HalfVectors(const Plan& plan, const VisitPlan& sample) {
  const HalfVectorAzimuths azimuths = plan.gantry.motion.half_vector_azimuths;
  std::string out;
  Append(&out,
         "half vectors (gantry.half_vector_azimuths: %s): a facet tilted up to %.0f deg lies at "
         "most %.1f deg from the nearest\n",
         ToString(azimuths), kReliefTiltDeg,
         RadToDeg(WidestHalfVectorGap(sample, DegToRad(kReliefTiltDeg))));
  if (azimuths == HalfVectorAzimuths::kSpread && sample.spread_tolerance_deg > 0)
    Append(&out,
           "  each pose within %.0f deg of its spread azimuth (the narrowest that leaves a "
           "collision-free route)\n",
           sample.spread_tolerance_deg);
  else if (azimuths == HalfVectorAzimuths::kSpread)
    out += "  no spread of the azimuths leaves a collision-free route: the fastest are used\n";
  if (plan.reconstruction.normals && azimuths == HalfVectorAzimuths::kFastest)
    out +=
        "  note: the normals are estimated and the half vectors may share one side of the "
        "normal, where a glossy ink's tilted facets show no highlight; "
        "gantry.half_vector_azimuths: spread puts them all round (what it trades: "
        "docs/reconstruction.md, "
        "\"Half vectors all round\")\n";
  return out;
}

}  // namespace

void CheckSessionInputs(const Plan& plan) {
  CheckPlanResources(plan);  // the basis, the output folder
  calib::ParseLensModel(plan.calibration.lensmodel, plan.calibration.lensmodel_where);
  if (plan.calibration.intrinsics_file.empty()) return;
  try {
    calib::CameraModel::Read(plan.calibration.intrinsics_file);
  } catch (const UserError& e) {
    throw UserError(plan.path + ": calibration.camera_model", e.what(),
                    "give a .cameramodel written by acqd or `acq calibrate intrinsics`");
  }
}

std::string DryRunText(const Plan& plan) {
  std::string out;
  Append(&out, "plan %s: backend %s, session directory %s\n", plan.path.c_str(),
         BackendName(plan.backend), plan.output.c_str());
  Append(&out, "sample %.0f x %.0f mm; %zu directions from %s; basis %s (k = %d)\n\n",
         plan.sample.width_mm, plan.sample.height_mm, plan.directions.size(),
         plan.directions_file.c_str(), plan.reconstruction.basis_file.c_str(),
         plan.reconstruction.components);
  const SessionVisits visits = PlanVisits(plan);
  const VisitPlan naive = PlanInFileOrder(plan.directions, plan.gantry.motion);
  out += VisitingOrder(plan, visits.sample) + "\n";
  out += HalfVectors(plan, visits.sample) + "\n";
  out += OverTheSample(plan) + "\n";
  double total_s = 0;
  out += Schedule(plan, visits, &total_s);
  out +=
      "  processing: HDR merge, calibration (intrinsics, cam_from_sample per pose), "
      "correspondence, reconstruction, validation renders, report\n";
  Append(&out,
         "\nestimated capture time, without the operator: %.1f s (the sample's %zu poses take "
         "%.1f s of motion a pass in this order, %.1f s in file order)\n",
         total_s, visits.sample.poses.size(), visits.sample.total_s, naive.total_s);
  return out;
}

}  // namespace acq
