#include "daemon/control.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/error.h"

namespace acq {
namespace {

std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      out += '\\', out += c;
    else if (c == '\n')
      out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20)
      out += ' ';
    else
      out += c;
  }
  return out + "\"";
}

sockaddr_un Address(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  if (path.size() >= sizeof a.sun_path)
    throw UserError(path, "socket path too long (" + std::to_string(path.size()) + " characters)",
                    "use a shorter path with --socket");
  std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
  return a;
}

}  // namespace

std::string SessionStatus::Json() const {
  char numbers[512];
  std::snprintf(numbers, sizeof numbers,
                "\"progress\": %.4f, \"eta_s\": %.1f, \"arms_deg\": [%.3f, %.3f, %.3f, %.3f], "
                "\"frames\": %ld, \"incomplete_frames\": %ld, \"retransmissions\": %ld",
                progress, eta_s, arms_deg[0], arms_deg[1], arms_deg[2], arms_deg[3], frames,
                incomplete_frames, retransmissions);
  return "{\"state\": " + Quoted(state) + ", \"step\": " + Quoted(step) + ", " + numbers +
         ", \"prompt\": " + Quoted(prompt) + ", \"last_error\": " + Quoted(last_error) + "}";
}

std::string DefaultControlSocket() {
  if (const char* run = std::getenv("XDG_RUNTIME_DIR"); run && *run)
    return std::string(run) + "/acqd.sock";
  return "/tmp/acqd-" + std::to_string(getuid()) + ".sock";
}

ControlServer::ControlServer(std::string path, bool shared_group) : path_(std::move(path)) {
  const sockaddr_un address = Address(path_);
  // Someone answering there is another acqd; a socket file nobody answers is stale.
  try {
    ControlRequest(path_, "status", 500);
    throw UserError(path_, "another acqd is running and answers on this control socket",
                    "stop it (`acqctl abort`) or give this one another --socket");
  } catch (const UserError& e) {
    if (e.problem().find("another acqd") != std::string::npos) throw;
  }
  ::unlink(path_.c_str());
  listener_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listener_ < 0)
    throw UserError(path_, std::string("cannot create a socket: ") + strerror(errno));
  // Created with the right mode from the start (no window in which others could connect).
  const mode_t old = ::umask(shared_group ? 0117 : 0177);
  const int bound = ::bind(listener_, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  ::umask(old);
  if (bound != 0 || ::listen(listener_, 8) != 0) {
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

std::string ControlServer::TakeCommand() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (commands_.empty()) return {};
  std::string c = commands_.front();
  commands_.pop_front();
  return c;
}

std::string ControlServer::Answer(const std::string& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (request == "status") return status_.Json();
  if (request == "pause" || request == "resume" || request == "abort" || request == "confirm") {
    commands_.push_back(request);
    return "ok " + request + " queued; the sequencer takes it at its next safe point";
  }
  return "error unknown request '" + request + "' (status, pause, resume, abort, confirm)";
}

void ControlServer::Serve() {
  while (!stop_) {
    pollfd p{listener_, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;  // 50 ms: how soon the destructor is noticed
    const int client = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    // One short request line; a client that sends nothing within 200 ms is dropped, so a stuck
    // client cannot hold up others.
    std::string line;
    char buffer[256];
    pollfd c{client, POLLIN, 0};
    while (line.find('\n') == std::string::npos && line.size() < 1024 && ::poll(&c, 1, 200) > 0) {
      const ssize_t n = ::read(client, buffer, sizeof buffer);
      if (n <= 0) break;
      line.append(buffer, std::size_t(n));
    }
    const std::string request = line.substr(0, line.find('\n'));
    const std::string reply = Answer(request) + "\n";
    (void)!::write(client, reply.data(), reply.size());
    ::close(client);
  }
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
  (void)!::write(fd, line.data(), line.size());
  std::string reply;
  char buffer[1024];
  pollfd p{fd, POLLIN, 0};
  while (reply.find('\n') == std::string::npos && ::poll(&p, 1, timeout_ms) > 0) {
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
