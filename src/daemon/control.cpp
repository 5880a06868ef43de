#include "daemon/control.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace acq {
namespace {

sockaddr_un Address(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  if (path.size() >= sizeof a.sun_path)
    throw UserError(path, "socket path too long (" + std::to_string(path.size()) + " characters)",
                    "use a shorter path with --socket");
  std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
  return a;
}

// Whether a process listens on the socket at `path` (connect succeeds), none does (the file is
// absent, or a socket file nobody listens on: refused), or that cannot be told.
enum class Listener { kNone, kStale, kLive };
Listener ProbeListener(const std::string& path, const sockaddr_un& address) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) return Listener::kNone;
  if (!S_ISSOCK(st.st_mode))
    throw UserError(path, "exists and is not a socket",
                    "give acqd a --socket path that is free (this file is left as it is)");
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw UserError(path, std::string("cannot create a socket: ") + strerror(errno));
  const int rc = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  const int e = errno;
  ::close(fd);
  if (rc == 0) return Listener::kLive;
  if (e == ECONNREFUSED) return Listener::kStale;
  throw UserError(path,
                  std::string("cannot tell whether an acqd listens here (") + strerror(e) + ")",
                  e == EACCES ? "the socket belongs to another user; give this acqd its own "
                                "--socket"
                              : "give this acqd another --socket");
}

double MsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

std::string DefaultControlSocket() {
  if (const char* run = std::getenv("XDG_RUNTIME_DIR"); run && *run)
    return std::string(run) + "/acqd.sock";
  return "/tmp/acqd-" + std::to_string(getuid()) + ".sock";
}

ControlServer::ControlServer(std::string path, bool shared_group) : path_(std::move(path)) {
  const sockaddr_un address = Address(path_);
  switch (ProbeListener(path_, address)) {
    case Listener::kLive:
      throw UserError(path_, "another acqd is running and listens on this control socket",
                      "stop it (`acqctl abort`) or give this one another --socket");
    case Listener::kStale:
      ::unlink(path_.c_str());  // a socket file whose acqd is gone
      break;
    case Listener::kNone:
      break;
  }
  listener_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (listener_ < 0)
    throw UserError(path_, std::string("cannot create a socket: ") + strerror(errno));
  // Created with the right mode from the start (no window in which others could connect).
  const mode_t old = ::umask(shared_group ? 0117 : 0177);
  const int bound = ::bind(listener_, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  ::umask(old);
  if (bound != 0 || ::listen(listener_, 64) != 0) {
    const std::string why = strerror(errno);
    ::close(listener_);
    throw UserError(path_, "cannot listen: " + why, "check the folder exists and is writable");
  }
  thread_ = std::thread([this] { Serve(); });
}

ControlServer::~ControlServer() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  ::close(listener_);
  ::unlink(path_.c_str());
}

void ControlServer::Publish(const SessionStatus& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_ = status;
}

void ControlServer::PublishFrame(const FramePreview& preview) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::uint64_t seq = frame_.seq + 1;
  frame_ = preview;
  frame_.seq = seq;
}

std::optional<ControlCommand> ControlServer::TakeCommand() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (commands_.empty()) return std::nullopt;
  const ControlCommand c = commands_.front();
  commands_.pop_front();
  return c;
}

// Called with mutex_ held.
std::string ControlServer::Confirm(const std::string& argument) {
  const int showing = status_.prompt.empty() ? 0 : status_.prompt_id;
  if (showing == 0)
    return "error no operator prompt is showing: there is nothing to confirm (`acqctl status` "
           "shows the prompt when there is one)";
  int id = showing;
  if (!argument.empty()) {
    char* end = nullptr;
    const long asked = std::strtol(argument.c_str(), &end, 10);
    if (*end != '\0' || asked <= 0)
      return "error confirm takes a prompt id (a whole number), not '" + argument + "'";
    id = int(asked);
  }
  if (id != showing)
    return "error prompt " + std::to_string(id) + " is not showing; prompt " +
           std::to_string(showing) + " is: " + status_.prompt;
  if (confirmed_prompt_ == id)
    return "error prompt " + std::to_string(id) + " is already confirmed";
  confirmed_prompt_ = id;
  commands_.push_back({CommandKind::kConfirm, id});
  return "ok confirm of prompt " + std::to_string(id) + " queued: " + status_.prompt;
}

// Called with mutex_ held. Only a preview takes an exposure: a session's come from its plan.
std::string ControlServer::Exposure(const std::string& argument) {
  if (status_.state != DaemonState::kPreview)
    return "error the exposure is set only in preview mode (acqd --preview); a session's "
           "exposures come from its plan";
  char* end = nullptr;
  const double us = std::strtod(argument.c_str(), &end);
  if (argument.empty() || *end != '\0' || !(us >= 1 && us <= 1e7))
    return "error exposure takes microseconds from 1 to 10000000, not '" + argument + "'";
  commands_.push_back({CommandKind::kExposure, 0, us});
  return "ok exposure " + argument + " us queued";
}

std::string ControlServer::Answer(const std::string& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (request == "status") return status_.Json();
  if (request == "frame") return frame_.Json();
  const std::size_t space = request.find(' ');
  const std::string verb = request.substr(0, space);
  const std::string argument = space == std::string::npos ? "" : request.substr(space + 1);
  const std::optional<CommandKind> kind = ParseCommandKind(verb);
  if (!kind)
    return "error unknown request '" + request + "' (status, frame, pause, resume, abort, confirm)";
  if (*kind == CommandKind::kConfirm) return Confirm(argument);
  if (*kind == CommandKind::kExposure) return Exposure(argument);
  if (!argument.empty()) return "error " + verb + " takes no argument";
  commands_.push_back({*kind, 0});
  return "ok " + verb + " queued; the sequencer takes it at its next safe point";
}

namespace {

struct Client {
  int fd;
  std::string line;
  std::chrono::steady_clock::time_point connected;
};

// A whole reply or nothing: a client that cannot take a line at once is not waited for.
void SendReply(int fd, const std::string& reply) {
  (void)!::send(fd, reply.data(), reply.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

}  // namespace

void ControlServer::Serve() {
  std::vector<Client> clients;
  while (!stop_) {
    std::vector<pollfd> fds{{listener_, POLLIN, 0}};
    for (const Client& c : clients) fds.push_back({c.fd, POLLIN, 0});
    ::poll(fds.data(), fds.size(), 50);  // 50 ms: how soon the destructor is noticed
    if (fds[0].revents & POLLIN) {
      for (int fd;
           (fd = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK)) >= 0;) {
        if (int(clients.size()) >= kMaxClients) {
          SendReply(fd, "error busy: " + std::to_string(kMaxClients) + " clients connected\n");
          ::close(fd);
          continue;
        }
        clients.push_back({fd, {}, std::chrono::steady_clock::now()});
      }
    }
    std::vector<Client> open;
    for (std::size_t i = 0; i < clients.size(); ++i) {
      Client& c = clients[i];
      bool finished = false;
      if (fds[i + 1].revents & (POLLIN | POLLHUP | POLLERR)) {
        char buffer[256];
        const ssize_t n = ::read(c.fd, buffer, sizeof buffer);
        if (n > 0) c.line.append(buffer, std::size_t(n));
        finished = n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR) ||
                   c.line.find('\n') != std::string::npos || c.line.size() >= 1024;
      }
      if (finished) {
        if (!c.line.empty()) SendReply(c.fd, Answer(c.line.substr(0, c.line.find('\n'))) + "\n");
        ::close(c.fd);
      } else if (MsSince(c.connected) > kClientDeadlineMs) {
        SendReply(c.fd,
                  "error no request line within " + std::to_string(kClientDeadlineMs) + " ms\n");
        ::close(c.fd);
      } else {
        open.push_back(c);
      }
    }
    clients.swap(open);
  }
  for (const Client& c : clients) ::close(c.fd);
}

std::string ControlRequest(const std::string& path, const std::string& request, int timeout_ms) {
  const sockaddr_un address = Address(path);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw UserError(path, "cannot create a socket");
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int e = errno;
    ::close(fd);
    throw UserError(path, std::string("no acqd answers here (") + strerror(e) + ")",
                    e == EACCES ? "the socket belongs to another user"
                                : "is acqd running? give its socket with --socket");
  }
  const std::string line = request + "\n";
  (void)!::send(fd, line.data(), line.size(), MSG_NOSIGNAL);
  std::string reply;
  char buffer[1024];
  pollfd p{fd, POLLIN, 0};
  const auto start = std::chrono::steady_clock::now();
  while (reply.find('\n') == std::string::npos) {
    const int left = timeout_ms - int(MsSince(start));
    if (left <= 0 || ::poll(&p, 1, left) <= 0) break;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) break;
    reply.append(buffer, std::size_t(n));
  }
  ::close(fd);
  if (reply.empty())
    throw UserError(path, "acqd did not answer within " + std::to_string(timeout_ms) + " ms");
  return reply.substr(0, reply.find('\n'));
}

}  // namespace acq
