// What a session publishes while it runs and the commands it takes at its safe points (issue
// 21): the types of the control protocol, below the socket. The sequencer (capture.h) talks to
// a StatusChannel; acqd's ControlServer (daemon/control.h) is the one that serves a socket, and
// an in-process test can be another.
#pragma once

#include <optional>
#include <string>

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
  kFailed
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
  std::string Json() const;  // one line; NaN and infinities as null
};

enum class CommandKind { kPause, kResume, kAbort, kConfirm };
const char* ToString(CommandKind k);
std::optional<CommandKind> ParseCommandKind(const std::string& text);

struct ControlCommand {
  CommandKind kind;
  int prompt_id = 0;  // kConfirm: the prompt it answers
};

// Where the sequencer publishes its status and takes operator commands.
class StatusChannel {
 public:
  virtual ~StatusChannel() = default;
  virtual void Publish(const SessionStatus& status) = 0;
  // The oldest command not yet taken, if any.
  virtual std::optional<ControlCommand> TakeCommand() = 0;
};

}  // namespace acq
