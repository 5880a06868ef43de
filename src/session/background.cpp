#include "session/background.h"

#include "core/seconds_since.h"
#include "session/view_correspondence.h"

namespace acq {

BackgroundProcessing::BackgroundProcessing(const Plan& plan)
    : plan_(plan), worker_([this] { Run(); }) {}

BackgroundProcessing::~BackgroundProcessing() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void BackgroundProcessing::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, all done
    std::function<void()> job = std::move(queue_.front());
    queue_.pop_front();
    working_ = true;
    lock.unlock();
    const auto start = SteadyClock::now();
    try {
      job();
    } catch (const std::exception&) {
      // Left for the processing, which does the same work again and reports the failure.
    }
    const double spent = SecondsSince(start);
    lock.lock();
    busy_s_ += spent;
    working_ = false;
    wake_.notify_all();
  }
}

void BackgroundProcessing::PoseCaptured(const std::string& dir, Step step, int pose,
                                        std::vector<CatalogFrame> frames) {
  std::lock_guard<std::mutex> lock(mutex_);
  queue_.push_back([this, dir, step, pose, frames = std::move(frames)] {
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
  wake_.notify_all();
}

void BackgroundProcessing::BoardsCaptured(SessionFrames session) {
  std::lock_guard<std::mutex> lock(mutex_);
  queue_.push_back([this, session = std::move(session)] {
    double seconds = 0;
    SessionCalibration c = CalibrateSession(plan_, session, &seconds);
    const calib::ReferenceView reference = ReferenceViewOf(plan_, c.camera);
    std::lock_guard<std::mutex> done(mutex_);
    calibration_ = std::move(c);
    reference_ = reference;
    results_.correspondence.clear();  // made for no calibration or another one
  });
  wake_.notify_all();
}

PrecomputedStages BackgroundProcessing::Finish() {
  std::unique_lock<std::mutex> lock(mutex_);
  wake_.wait(lock, [&] { return queue_.empty() && !working_; });
  PrecomputedStages out = std::move(results_);
  out.calibration = calibration_;
  results_ = {};
  return out;
}

double BackgroundProcessing::busy_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return busy_s_;
}

int BackgroundProcessing::poses_merged() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return poses_merged_;
}

}  // namespace acq
