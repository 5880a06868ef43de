// Replay (issue 8): a gantry that goes wherever a recorded session's frames were taken, at once,
// and reports the arm angles measured then, so that a recorded session runs through acqd's
// sequencer again (with ReplayCamera serving its frames) and is processed by the same code as a
// live one. A move to a pose the recording never held is refused, naming it: the plan is not
// the one the session was recorded with.
#pragma once

#include <string>
#include <vector>

#include "hw/gantry.h"

namespace acq {

class ReplayGantry : public Gantry {
 public:
  // The frame files of the recorded session (their arms_commanded_deg and arms_measured_deg
  // attributes; the pixels are not read). Throws UserError naming a file without them.
  explicit ReplayGantry(const std::vector<std::string>& frame_files);

  void Home() override;
  void MoveTo(const ArmAngles& target) override;
  void Stop() override {}
  void EmergencyStop() override {}
  GantryStatus Status() override { return status_; }
  void SetLight(bool, double) override {}
  void RenewLease(int) override {}
  void ClearFaults(std::uint16_t) override {}

 private:
  struct RecordedPose {
    ArmAngles commanded, measured;
  };
  std::vector<RecordedPose> poses_;  // one per recorded frame, in the order taken
  std::size_t next_ = 0;             // where to look for the next move's pose
  GantryStatus status_;
};

}  // namespace acq
