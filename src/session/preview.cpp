#include "session/preview.h"

#include <chrono>
#include <thread>

#include "core/error.h"
#include "core/stop_request.h"
#include "session/frame_preview.h"

namespace acq {

void RunPreview(const Plan& plan, Camera& camera, StatusChannel& control, SessionStatus& status,
                const PreviewOptions& options) {
  CameraSettings settings = plan.camera.settings;
  if (!plan.camera.bracket_us.empty()) settings.exposure_us = plan.camera.bracket_us.front();
  const auto period = std::chrono::duration<double>(1 / std::max(options.frames_per_second, 0.1));
  status.state = DaemonState::kPreview;
  bool apply = true;
  for (long n = 0; options.max_frames == 0 || n < options.max_frames; ++n) {
    const auto start = std::chrono::steady_clock::now();
    ThrowIfStopRequested();
    for (std::optional<ControlCommand> c = control.TakeCommand(); c; c = control.TakeCommand()) {
      if (c->kind == CommandKind::kAbort) {
        status.state = DaemonState::kAborted;
        status.step = "preview ended by the operator";
        control.Publish(status);
        return;
      }
      if (c->kind == CommandKind::kExposure) settings.exposure_us = c->value, apply = true;
    }
    try {
      if (apply) camera.Apply(settings), apply = false;
      FramePreview preview = PreviewOf(camera.Grab());
      status.step = "preview: exposure " + std::to_string(long(settings.exposure_us)) + " us";
      preview.step = status.step;
      ++status.frames;
      status.incomplete_frames = long(camera.Statistics().incomplete);
      control.PublishFrame(preview);
      control.Publish(status);
    } catch (const UserError& e) {
      status.state = DaemonState::kFailed;
      status.last_error = e.what();
      control.Publish(status);
      throw;
    }
    std::this_thread::sleep_until(start + period);
  }
}

}  // namespace acq
