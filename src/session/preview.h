// acqd's preview mode (issue 23; docs/live-view.md): the camera alone, streaming to the live
// view at a few frames a second so that the operator can place and focus the sample before a
// session. Nothing moves and nothing is written into the session. The exposure starts at the
// plan's (its bracket's shortest for an HDR plan) and follows `acqctl`'s `exposure US` (the live
// view's exposure field); abort, SIGINT or SIGTERM end it.
#pragma once

#include "acq/plan.h"
#include "hw/camera.h"
#include "session/status.h"

namespace acq {

struct PreviewOptions {
  double frames_per_second = 4;  // at most: a grab takes what it takes
  long max_frames = 0;           // 0: until aborted or stopped (tests end sooner)
};

// Returns when aborted (or after max_frames); throws Stopped on SIGINT/SIGTERM and the camera's
// UserError when it fails (published as the last error first).
void RunPreview(const Plan& plan, Camera& camera, StatusChannel& control, SessionStatus& status,
                const PreviewOptions& options = {});

}  // namespace acq
