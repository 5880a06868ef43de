// The sequencer's capture steps (issue 8): every pose of a visiting order, its HDR bracket,
// each frame written atomically into the session and then recorded in the catalog; frames the
// catalog already has are skipped, so a resumed session takes exactly the frames that are
// missing. Between frames (the safe points) the status is published and operator commands are
// taken: pause waits for resume, abort stops the gantry and leaves the session resumable.
//
// Steps: "sample" (the sample at the plan's directions), "validation" (the sample at the
// validation directions, never used to reconstruct), "spectralon" and "spectralon_validation"
// (the Spectralon board at the same poses: the light's irradiance per view). Before a step
// whose item (sample, spectralon) is not the one under the gantry, the item is placed: by the
// operator (a prompt on the control socket, answered with `acqctl confirm`) or, in simulation,
// by the simulated world.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "acq/move_planner.h"
#include "acq/plan.h"
#include "core/seconds_since.h"
#include "daemon/control.h"
#include "hw/camera.h"
#include "hw/gantry.h"
#include "io/session_catalog.h"

namespace acq {

struct CaptureReport {
  int frames_taken = 0, frames_skipped = 0;
  double motion_s = 0, exposure_s = 0, transfer_s = 0;  // where the time went
  double bracket_probe_s = 0;                           // choosing automatic brackets
  double operator_s = 0;                                // waiting for the operator
  CaptureReport& operator+=(const CaptureReport& o);
};

struct CaptureStep {
  std::string step;  // the catalog's step name
  std::string item;  // what must lie under the gantry: "sample" or "spectralon"
  const VisitPlan* visit = nullptr;
  const std::vector<Direction>* directions = nullptr;  // visit's poses index these
};

// The steps of a plan in capture order (the sample's, then the Spectralon's, so the operator
// changes the item once).
std::vector<CaptureStep> CaptureSteps(const Plan& plan, const VisitPlan& sample,
                                      const VisitPlan& validation);

struct CaptureContext {
  Gantry& gantry;
  Camera& camera;
  SessionCatalog& catalog;
  ControlServer& control;
  SessionStatus& status;
  // Places an item under the gantry without an operator (the simulated world); empty: ask.
  std::function<void(const std::string& item)> place;
  std::string placed;  // the item known to be under the gantry ("" after a restart)
  int poses_done = 0, poses_total = 0;  // for the progress over the whole session
  int poses_taken = 0;                  // this run: the rate the ETA is estimated from
  SteadyClock::time_point started = SteadyClock::now();
};

// Captures one step. Throws UserError on an abort (the gantry stopped) and on device failures.
CaptureReport Capture(const Plan& plan, const CaptureStep& step, CaptureContext& context);

}  // namespace acq
