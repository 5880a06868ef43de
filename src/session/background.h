// Processing that overlaps the capture (issue 8): on a worker thread, each pose's HDR merge as
// soon as its frames are in, the calibration as soon as the board steps are captured, and from
// then on each view of the sample's correspondence map (issue 21), while the gantry moves on. It
// writes what the processing would (hdr/, calibration/); the processing then reads the merges back
// (pose_hdr.h reuses an up-to-date hdr file) and takes the calibration as computed. A failure here
// is dropped: the processing meets it again and reports it properly.
#pragma once

#include <mutex>
#include <optional>
#include <string>

#include "acq/plan.h"
#include "calib/correspondence.h"
#include "session/pose_hdr.h"
#include "session/process.h"
#include "session/serial_worker.h"
#include "session/session_calibration.h"
#include "session/view_correspondence.h"

namespace acq {

class BackgroundProcessing {
 public:
  explicit BackgroundProcessing(const Plan& plan) : plan_(plan) {}
  ~BackgroundProcessing() = default;  // finishes what is queued

  // A pose's frames are all in the session (`frames`: those of the pose).
  void PoseCaptured(const std::string& dir, Step step, int pose, std::vector<CatalogFrame> frames);
  // The board steps are captured: `session` holds their frames.
  void BoardsCaptured(SessionFrames session);
  // Waits for the queue; what it computed: the calibration, the merged poses, the views'
  // correspondence maps (for that calibration).
  PrecomputedStages Finish();

  double busy_s() const { return worker_.busy_s(); }  // (overlapping the capture, mostly)
  int poses_merged() const;

 private:
  const Plan plan_;
  mutable std::mutex mutex_;  // results_ and poses_merged_, read by the capture's thread
  std::optional<SessionCalibration> calibration_;  // set and read by the worker
  std::optional<SessionReference> reference_;      // the calibrated camera's, with it
  PrecomputedStages results_;                      // merges and correspondence, for Finish()
  int poses_merged_ = 0;
  SerialWorker worker_{SerialWorker::OnFailure::kDrop};  // last: goes first
};

}  // namespace acq
