// A stop asked for by a signal (SIGTERM, SIGINT: issue 22), seen by every long loop of the
// daemon at its next safe point: the capture's safe points and waits, a move's or homing's
// wait, the stages of processing. The signal handler only sets a flag; whoever sees it throws
// Stopped, and the daemon's top level stops the gantry, records the stop and exits resumable.
#pragma once

#include <signal.h>

#include <atomic>
#include <string>

#include "core/error.h"

namespace acq {

// The signal that asked for the stop, 0 when none did.
inline std::atomic<int>& StopSignal() {
  static std::atomic<int> signal_number{0};
  return signal_number;
}

inline bool StopRequested() {
  return StopSignal().load() != 0;
}

// Thrown where a stop is seen; a UserError so that every tool reports it as a message.
class Stopped : public UserError {
 public:
  explicit Stopped(int signal_number)
      : UserError("acqd", "stopped by " + SignalName(signal_number),
                  "the gantry is stopped; run acqd again with the same plan to resume"),
        signal_(signal_number) {}
  int signal_number() const { return signal_; }

 private:
  static std::string SignalName(int s) {
    return s == SIGTERM ? "SIGTERM" : s == SIGINT ? "SIGINT" : "signal " + std::to_string(s);
  }
  int signal_;
};

inline void ThrowIfStopRequested() {
  if (const int s = StopSignal().load()) throw Stopped(s);
}

// SIGTERM and SIGINT ask for a stop (a second one of either ends the process at once, for an
// operator whose stop did not take); SIGPIPE is ignored, so a vanished peer is an error on its
// write, never the daemon's death.
inline void InstallStopHandlers() {
  struct sigaction stop {};
  stop.sa_handler = [](int s) {
    if (StopSignal().exchange(s) != 0) {
      ::signal(s, SIG_DFL);
      ::raise(s);
    }
  };
  sigemptyset(&stop.sa_mask);
  stop.sa_flags = SA_RESTART;  // device libraries' reads and writes go on; the flag is polled
  sigaction(SIGTERM, &stop, nullptr);
  sigaction(SIGINT, &stop, nullptr);
  ::signal(SIGPIPE, SIG_IGN);
}

}  // namespace acq
