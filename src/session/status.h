// What a session publishes while it runs and the commands it takes at its safe points (issue
// 21): the types of the control protocol, below the socket. The sequencer (capture.h) talks to
// a StatusChannel; acqd's ControlServer (daemon/control.h) is the one that serves a socket, and
// an in-process test can be another.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace acq {

// What acqd is doing, as `acqctl status` shows it.
enum class DaemonState {
  kStarting,
  kRunning,
  kPaused,
  kWaiting,
  kAborted,
  kStopped,
  kDone,
  kFailed,
  kPreview  // acqd --preview: the camera streaming to the live view, nothing moved or recorded
};
const char* ToString(DaemonState s);
std::optional<DaemonState> ParseDaemonState(const std::string& text);
// A state the daemon does not leave (acqctl watch stops there).
bool IsFinal(DaemonState s);

struct SessionStatus {
  DaemonState state = DaemonState::kStarting;
  std::string step;                   // "sample pose 7 of 20, exposure 2 of 3"
  double progress = 0;                // 0..1 over the whole session
  double eta_s = -1;                  // seconds left, -1 unknown
  double arms_deg[4] = {0, 0, 0, 0};  // light theta/phi, camera theta/phi (measured)
  std::string prompt;                 // what an operator must do before `acqctl confirm`
  int prompt_id = 0;                  // the prompt's id while one shows (1, 2, ...), else 0
  long frames = 0, incomplete_frames = 0, retransmissions = 0;
  std::string last_error;
  std::string session;  // the session's folder, absolute (its renders and report, once written)
  std::string Json() const;  // one line; NaN and infinities as null
};

enum class CommandKind { kPause, kResume, kAbort, kConfirm, kExposure };
const char* ToString(CommandKind k);
std::optional<CommandKind> ParseCommandKind(const std::string& text);

struct ControlCommand {
  CommandKind kind;
  int prompt_id = 0;  // kConfirm: the prompt it answers
  double value = 0;   // kExposure: microseconds (preview only)
};

// A small grey copy of the latest frame and its exposure's statistics, for a live view
// (issue 23; frame_preview.h makes one from a frame).
struct FramePreview {
  std::uint64_t seq = 0;  // 1, 2, ... in the order published (the channel numbers them); 0: none
  int width = 0, height = 0;                // the preview's
  int source_width = 0, source_height = 0;  // the frame's
  double exposure_us = 0;
  std::string step;                  // what it was taken for (the status's step then)
  std::vector<std::uint8_t> grey;    // width x height, value / max with a 1/2.2 display gamma
  std::array<long, 32> histogram{};  // value / max over the sampled blocks, 32 equal bins
  long sampled = 0, clipped = 0;     // 2 x 2 blocks sampled, and those with a pixel at the max
  // The focus aid: the frame's centre at full 2 x 2 block resolution (nothing skipped, so that
  // the operator sees what the 192-pixel preview hides), and a sharpness figure of it.
  int focus_width = 0, focus_height = 0;
  std::vector<std::uint8_t> focus_grey;  // as grey, same gamma
  double sharpness = 0;      // frame_preview.h's definition; higher is sharper, exposure cancels
  std::string Json() const;  // one line; the pixels in base64
};

// Where the sequencer publishes its status and takes operator commands.
class StatusChannel {
 public:
  virtual ~StatusChannel() = default;
  virtual void Publish(const SessionStatus& status) = 0;
  // The latest frame's preview, for a live view; channels without one ignore it.
  virtual void PublishFrame(const FramePreview&) {}
  // The oldest command not yet taken, if any.
  virtual std::optional<ControlCommand> TakeCommand() = 0;
};

}  // namespace acq
