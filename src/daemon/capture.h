// The sample's captures (issue 8, the first stage of the sequencer): every pose of the visiting
// order, its HDR bracket, each frame written atomically into the session and then recorded in
// the catalog; frames the catalog already has are skipped, so a resumed session takes exactly
// the frames that are missing. Between frames (the safe points) the status is published and
// operator commands are taken: pause waits for resume, abort stops the gantry and leaves the
// session resumable.
#pragma once

#include <string>

#include "acq/move_planner.h"
#include "acq/plan.h"
#include "daemon/control.h"
#include "hw/camera.h"
#include "hw/gantry.h"
#include "io/session_catalog.h"

namespace acq {

struct CaptureReport {
  int frames_taken = 0, frames_skipped = 0;
  double motion_s = 0, exposure_s = 0, transfer_s = 0;  // where the time went
};

// Throws UserError on an abort (the gantry stopped) and on device failures.
CaptureReport CaptureSample(const Plan& plan, const VisitPlan& visit, Gantry& gantry,
                            Camera& camera, SessionCatalog& catalog, ControlServer& control);

}  // namespace acq
