// acqd's control channel (issue 8): a Unix-domain socket, owner-only by default, that answers
// `acqctl` without ever waiting for the sequencer. The sequencer publishes its state into a
// SessionStatus snapshot (under a mutex held only to copy it); the server thread answers from
// the latest snapshot, so status comes back at once even while the sequencer is busy or stuck.
// Commands (pause, resume, abort, confirm) are queued for the sequencer to take at its next
// safe point.
//
// Protocol: one request line ("status", "pause", "resume", "abort", "confirm"), one reply line
// (status: a JSON object; commands: "ok ..." or "error ...").
#pragma once

#include <atomic>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

namespace acq {

struct SessionStatus {
  std::string state = "starting";     // starting, running, paused, waiting, aborting, done, failed
  std::string step;                   // "sample pose 7 of 20, exposure 2 of 3"
  double progress = 0;                // 0..1 over the whole session
  double eta_s = -1;                  // seconds left, -1 unknown
  double arms_deg[4] = {0, 0, 0, 0};  // light theta/phi, camera theta/phi (measured)
  std::string prompt;                 // what an operator must do before `acqctl confirm`
  long frames = 0, incomplete_frames = 0, retransmissions = 0;
  std::string last_error;
  std::string Json() const;
};

// The default socket: $XDG_RUNTIME_DIR/acqd.sock, else /tmp/acqd-<uid>.sock.
std::string DefaultControlSocket();

class ControlServer {
 public:
  // Binds `path` with mode 0600 (`shared_group`: 0660). Throws UserError when another acqd
  // answers there; a stale socket left by a killed acqd is replaced.
  explicit ControlServer(std::string path, bool shared_group = false);
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  void Publish(const SessionStatus& status);
  // The oldest command not yet taken ("pause", ...), or "" when none.
  std::string TakeCommand();
  const std::string& path() const { return path_; }

 private:
  void Serve();
  std::string Answer(const std::string& request);

  std::string path_;
  int listener_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::mutex mutex_;
  SessionStatus status_;
  std::deque<std::string> commands_;
};

// One request to the daemon at `path`; the reply line. Throws UserError when no acqd answers.
std::string ControlRequest(const std::string& path, const std::string& request,
                           int timeout_ms = 2000);

}  // namespace acq
