// A whole session as a library function (issue 21): what acqd does between reading its plan and
// exiting, on devices its caller opens. The session is taken (its lock), its catalog verified
// and repaired (a resume takes exactly what is missing), the devices opened (only then: an
// absent or wrong one ends the run before anything moves, having deleted nothing), the gantry
// homed, every capture step taken (capture.h) with processing overlapping it (background.h),
// the session processed (process.h), optionally scored, and the report written. A failure is
// recorded in the catalog and published as the last error before it is re-thrown; the frames
// taken stay, and running the same plan again resumes.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "acq/plan.h"
#include "hw/camera.h"
#include "hw/gantry.h"
#include "hw/replay_camera.h"
#include "session/report.h"
#include "session/status.h"

namespace acq {

// The devices a session runs on, and how the items get under the gantry.
struct SessionDevices {
  std::unique_ptr<Gantry> gantry;
  std::unique_ptr<Camera> camera;
  std::string gantry_id;  // recorded with every frame
  // A replay (the recording's frames and arm angles stand in for both devices): set to the
  // camera, so that the recorded decisions are reused and a resumed replay skips what it took.
  ReplayCamera* replay = nullptr;
  // Ask the operator at every placement (a prompt; `acqctl confirm`); `place`, where given,
  // follows (the simulated instrument) or, without asking, places alone.
  bool ask_operator = true;
  std::function<void(const Placement&)> place;
  // The light's intensity in HDR units where no Spectralon measures it (simulation), else 0.
  double light_intensity = 0;
};

struct SessionHooks {
  // Opens the devices once the catalog is verified; `phase` shows what is being done.
  std::function<SessionDevices(const std::function<void(const std::string&)>& phase)> open;
  // Scores the processed session (simulation: against the truth), before the report is written.
  std::function<void(SessionReport*)> score;
};

// Runs the session of `plan` to its report; returns it (also written as report.json/.txt).
// `status` is published through `control` all along and ends kDone; throws on a failure (after
// publishing it), UserError on an operator's abort, Stopped on a stop signal.
SessionReport RunSession(const Plan& plan, StatusChannel& control, SessionStatus& status,
                         const SessionHooks& hooks);

// The devices of a replay of plan.replay_session (ReplayGantry, ReplayCamera).
SessionDevices OpenReplayDevices(const Plan& plan);

}  // namespace acq
