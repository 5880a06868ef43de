// The sequencer's capture steps (issue 8): every pose of a visiting order, its HDR bracket,
// each frame written atomically into the session and then recorded in the catalog; frames the
// catalog already has are skipped, so a resumed session takes exactly the frames that are
// missing. Between frames (the safe points) the status is published and operator commands are
// taken: pause waits for resume, abort stops the gantry and leaves the session resumable.
//
// Steps, in capture order (core/session_vocabulary.h): intrinsics (the chessboard held in a new
// pose for every capture, the camera straight above the sample: the lens's intrinsics), board and
// board_validation (the chessboard flat on the sample plane at every pose of the sample's and the
// validation's visits: each view's cam_from_sample, and the board defines the sample frame),
// sample (the sample at the plan's directions), validation (the sample at the validation
// directions, never used to reconstruct), spectralon and spectralon_validation (the Spectralon
// board at the same poses: the light's irradiance per view). Before a capture whose placement (a
// held board pose, the board, the sample, the Spectralon) is not the one under the gantry, it is
// placed: by the operator (a prompt on the control socket, answered with `acqctl confirm`) or, in
// simulation, by the simulated instrument.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "acq/move_planner.h"
#include "acq/plan.h"
#include "core/seconds_since.h"
#include "core/session_vocabulary.h"
#include "hw/camera.h"
#include "hw/gantry.h"
#include "io/session_catalog.h"
#include "session/frame_writer.h"
#include "session/status.h"

namespace acq {

struct CaptureReport {
  int frames_taken = 0, frames_skipped = 0;
  double motion_s = 0, exposure_s = 0, transfer_s = 0;  // where the time went
  double bracket_probe_s = 0;                           // choosing automatic brackets
  double settings_s = 0;  // the camera taking each frame's exposure (a control round trip)
  double operator_s = 0;  // waiting for the operator
  CaptureReport& operator+=(const CaptureReport& o);
};

struct CaptureStep {
  Step step = Step::kSample;
  const VisitPlan* visit = nullptr;
  const std::vector<Direction>* directions = nullptr;  // visit's poses index these
  bool new_placement_per_pose = false;  // the board is held anew for every pose ("board/K")
  // > 0: exposures chosen at each pose (and recorded), at most this many, whatever the plan's
  // bracket; 0: the plan's bracket, fixed or automatic.
  int max_auto_frames = 0;
  // What must lie under the gantry for pose `pose` (0-based) of the step.
  Placement PlacementAt(std::size_t pose) const {
    return {ItemOf(step), new_placement_per_pose ? int(pose) + 1 : 0};
  }
};

// Where the intrinsics captures are taken: the camera straight above the sample, the light 30
// degrees from it (lighting a held board from the front).
std::vector<Direction> IntrinsicsDirection();

// The visits a session's capture steps take, planned once.
struct SessionVisits {
  VisitPlan intrinsics;  // the intrinsics pose, once per capture
  VisitPlan sample, validation;
  VisitPlan chart;  // the sample's first pose again, for the colour chart (or none)
  std::vector<Direction> intrinsics_direction = IntrinsicsDirection();
};
SessionVisits PlanVisits(const Plan& plan);

// Empty when a frame already in the session (its attributes) was taken at the arms this run
// commands for its pose, else what differs. A session resumed by an acqd whose planner visits
// the directions in another order would otherwise count one direction's frames as another's,
// never take the one left out, and merge two azimuths in one bracket.
// UserError naming `where` (the frame) when its arms attribute cannot be read.
std::string PoseMismatch(const PlannedPose& planned,
                         const std::map<std::string, std::string>& frame_attributes,
                         const std::string& where);

// The steps of a plan in capture order (the calibration boards', then the sample's, then the
// Spectralon's, so the operator changes the item as few times as can be).
std::vector<CaptureStep> CaptureSteps(const Plan& plan, const SessionVisits& visits);

struct CaptureContext {
  Gantry& gantry;
  Camera& camera;
  SessionCatalog& catalog;
  FrameWriter& writer;     // every frame goes into the session through it
  StatusChannel& control;  // acqd: its control socket
  SessionStatus& status;
  std::string gantry_id;  // recorded with every frame
  // Ask the operator to place each item (prompt, `acqctl confirm`); then `place`, where given,
  // follows the confirmation (the simulated world). Without asking, `place` places it.
  bool ask_operator = true;
  std::function<void(const Placement&)> place;
  std::optional<Placement> placed{};  // known to be under the gantry (none after a restart)
  int prompts_shown = 0;              // operator prompts shown by this run: the next one's id
  // Told when a pose's frames are all in the session (taken now or before; on the writer's
  // thread, once they are recorded), and when a step is captured (on the capture's thread, its
  // frames all recorded): processing that can start then (background.h).
  std::function<void(Step step, int pose)> pose_captured{};
  std::function<void(Step step)> step_captured{};
  int poses_done = 0, poses_total = 0;  // for the progress over the whole session
  int poses_taken = 0;                  // this run: the rate the ETA is estimated from
  SteadyClock::time_point started = SteadyClock::now();
};

// Captures one step. Throws UserError on an abort (the gantry stopped) and on device failures.
CaptureReport Capture(const Plan& plan, const CaptureStep& step, CaptureContext& context);

}  // namespace acq
