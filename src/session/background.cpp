#include "session/background.h"

#include "session/view_correspondence.h"

namespace acq {

void BackgroundProcessing::PoseCaptured(const std::string& dir, Step step, int pose,
                                        std::vector<CatalogFrame> frames) {
  // A failure here is dropped: the processing meets it again and reports it properly.
  worker_.Post([this, dir, step, pose, frames = std::move(frames)] {
    double seconds = 0;
    PoseHdr merged = MergePose(dir, step, pose, frames, &seconds);
    // A view of the sample, once the calibration is in (the board steps come first): its
    // correspondence map too. Both kept for the processing (the boards' merges are not: the
    // calibration has used them).
    std::optional<FloatPlanes> correspondence;
    const BoardPoseResult* board =
        calibration_ && ItemOf(step) == Item::kSample ? calibration_->PoseOf(step, pose) : nullptr;
    if (board)
      correspondence = PoseCorrespondence(
          dir, step, pose, *reference_,
          CalibratedViewOf(plan_, calibration_->camera, *board, merged.arms), &seconds);
    std::lock_guard<std::mutex> done(mutex_);
    ++poses_merged_;
    if (ItemOf(step) == Item::kBoard) return;
    results_.poses[{step, pose}] = std::move(merged);
    if (correspondence) results_.correspondence[{step, pose}] = std::move(*correspondence);
  });
}

void BackgroundProcessing::BoardsCaptured(SessionFrames session) {
  worker_.Post([this, session = std::move(session)] {
    double seconds = 0;
    SessionCalibration c = CalibrateSession(plan_, session, &seconds);
    SessionReference reference(ReferenceViewOf(plan_, c.camera));
    std::lock_guard<std::mutex> done(mutex_);
    calibration_ = std::move(c);
    reference_.emplace(std::move(reference));
    results_.correspondence.clear();  // made for no calibration or another one
  });
}

PrecomputedStages BackgroundProcessing::Finish() {
  worker_.Wait();
  std::lock_guard<std::mutex> lock(mutex_);
  PrecomputedStages out = std::move(results_);
  out.calibration = calibration_;
  results_ = {};
  return out;
}

int BackgroundProcessing::poses_merged() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return poses_merged_;
}

}  // namespace acq
