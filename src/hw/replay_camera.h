// Replay (issue 6): a camera that serves the frames of a recorded session, in the order they
// were taken, so processing can be re-run on real data through the same code as a capture.
// Apply() is checked against what was recorded: a session replayed with other settings (another
// plan, another bracket) is refused at the first frame that differs, naming it.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "hw/camera.h"

namespace acq {

class ReplayCamera : public Camera {
 public:
  // `session` is a session directory (its frames served in the order its catalog recorded
  // them) or a folder of frame files (served in name order). Throws UserError when there are
  // none.
  explicit ReplayCamera(const std::string& session);

  void Apply(const CameraSettings& settings) override;
  Frame Grab() override;
  StreamStatistics Statistics() const override { return stats_; }
  std::string Describe() const override { return "replay of " + folder_; }
  std::size_t remaining() const { return files_.size() - next_; }
  const std::vector<std::string>& files() const { return files_; }
  // Serves from the n-th frame on (a resumed replay has the first n already).
  void Skip(std::size_t n) { next_ = std::min(n, files_.size()); }

 private:
  std::string folder_;
  std::vector<std::string> files_;
  std::size_t next_ = 0;
  CameraSettings settings_;
  bool have_settings_ = false;
  StreamStatistics stats_;
};

}  // namespace acq
