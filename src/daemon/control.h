// acqd's control channel (issue 8): a Unix-domain socket, owner-only by default, that answers
// `acqctl` without ever waiting for the sequencer. The sequencer publishes its state into a
// SessionStatus snapshot (under a mutex held only to copy it); the server thread answers from
// the latest snapshot, so status comes back at once even while the sequencer is busy or stuck.
// Commands (pause, resume, abort, confirm) are queued for the sequencer to take at its next
// safe point.
//
// Protocol: one request line ("status", "frame", "pause", "resume", "abort", "confirm
// [PROMPT_ID]", "exposure US" in preview mode only), one reply line (status: a JSON object; frame:
// the latest frame's preview as a JSON object, session/status.h's FramePreview, seq 0 before the
// first; commands: "ok ..." or "error ..."). A confirmation counts only for the operator prompt
// showing when it arrives (issue 22): each prompt has an id, a confirm while none shows, or naming
// a prompt no longer showing, is refused.
//
// The server multiplexes its clients with poll (issue 22): a slow or silent client holds only
// its own slot (each has a deadline), never another's answer; replies are sent without SIGPIPE.
#pragma once

#include <atomic>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "session/status.h"

namespace acq {

// The default socket: $XDG_RUNTIME_DIR/acqd.sock, else /tmp/acqd-<uid>.sock.
std::string DefaultControlSocket();

class ControlServer : public StatusChannel {
 public:
  // Binds `path` with mode 0600 (`shared_group`: 0660). Throws UserError when another acqd
  // listens there, or when `path` exists and is not a socket (it is never deleted then); a
  // socket file nobody listens on (left by a killed acqd) is replaced.
  explicit ControlServer(std::string path, bool shared_group = false);
  ~ControlServer();  // stops serving and removes the socket
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  void Publish(const SessionStatus& status) override;
  void PublishFrame(const FramePreview& preview) override;
  std::optional<ControlCommand> TakeCommand() override;
  const std::string& path() const { return path_; }

  // At most this many clients at once; one more is answered "error busy" and closed.
  static constexpr int kMaxClients = 32;
  // A client must send its request line within this time of connecting.
  static constexpr int kClientDeadlineMs = 2000;

 private:
  void Serve();
  std::string Answer(const std::string& request);
  std::string Confirm(const std::string& argument);
  std::string Exposure(const std::string& argument);

  std::string path_;
  int listener_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::mutex mutex_;
  SessionStatus status_;
  FramePreview frame_;        // the latest, numbered here
  int confirmed_prompt_ = 0;  // the last prompt a confirm was accepted for
  std::deque<ControlCommand> commands_;
};

// One request to the daemon at `path`; the reply line. Throws UserError when no acqd answers.
std::string ControlRequest(const std::string& path, const std::string& request,
                           int timeout_ms = 2000);

}  // namespace acq
