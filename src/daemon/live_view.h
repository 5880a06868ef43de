// `acqctl serve` (issue 23; docs/live-view.md): the operator's live view, a web page served on
// this machine that shows acqd's status and latest frame and sends the operator's confirm and
// abort. Every request needs the access token printed at start (a query parameter `token` or
// the header X-Acq-Token); the server binds 127.0.0.1 unless told otherwise, and says so when
// told. It holds no state of acqd's: each request asks acqd over the control socket, so acqd
// not running (or ending while watched) is a page that says so and retries.
#pragma once

#include <string>

namespace acq {

struct LiveViewOptions {
  std::string socket;              // acqd's control socket
  std::string bind = "127.0.0.1";  // anything else serves beyond this machine
  int port = 8080;                 // 0: any free port (printed)
  std::string token;               // empty: a random one
  std::string session;             // a session folder to show until acqd reports one
  void Check() const;              // throws UserError
};

// Serves until SIGINT or SIGTERM; the exit code.
int ServeLiveView(LiveViewOptions options);

}  // namespace acq
