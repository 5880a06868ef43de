// Processing that overlaps the capture (issue 8): on a worker thread, each pose's HDR merge as
// soon as its frames are in, the calibration as soon as the board steps are captured, and from
// then on each view of the sample's correspondence map (issue 21), while the gantry moves on. It
// writes what the processing would (hdr/, calibration/); the processing then reads the merges back
// (pose_hdr.h reuses an up-to-date hdr file) and takes the calibration as computed. A failure here
// is dropped: the processing meets it again and reports it properly.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "acq/plan.h"
#include "calib/correspondence.h"
#include "session/pose_hdr.h"
#include "session/process.h"
#include "session/session_calibration.h"

namespace acq {

class BackgroundProcessing {
 public:
  explicit BackgroundProcessing(const Plan& plan);
  ~BackgroundProcessing();  // finishes what is queued
  BackgroundProcessing(const BackgroundProcessing&) = delete;
  BackgroundProcessing& operator=(const BackgroundProcessing&) = delete;

  // A pose's frames are all in the session (`frames`: those of the pose).
  void PoseCaptured(const std::string& dir, Step step, int pose, std::vector<CatalogFrame> frames);
  // The board steps are captured: `session` holds their frames.
  void BoardsCaptured(SessionFrames session);
  // Waits for the queue; what it computed: the calibration, the merged poses, the views'
  // correspondence maps (for that calibration).
  PrecomputedStages Finish();

  double busy_s() const;  // worker time spent (overlapping the capture, mostly)
  int poses_merged() const;

 private:
  void Run();
  const Plan plan_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> queue_;
  bool stopping_ = false, working_ = false;
  std::optional<SessionCalibration> calibration_;  // set and read by the worker
  std::optional<calib::ReferenceView> reference_;  // the calibrated camera's, with it
  PrecomputedStages results_;                      // merges and correspondence, for Finish()
  double busy_s_ = 0;
  int poses_merged_ = 0;
  std::thread worker_;
};

}  // namespace acq
