#include "io/session_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>

#include "core/error.h"

namespace acq {
namespace {

std::string ReadAll(int fd) {
  std::string text;
  char buffer[512];
  ::lseek(fd, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, std::size_t(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  return text;
}

std::string HostName() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  return host;
}

}  // namespace

SessionLock::SessionLock(const std::string& session_dir, const std::string& program)
    : path_((std::filesystem::path(session_dir) / "acqd.lock").string()) {
  std::error_code ec;
  std::filesystem::create_directories(session_dir, ec);
  if (ec) throw UserError(session_dir, "cannot create the session directory: " + ec.message());
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw UserError(path_, std::string("cannot open the session's lock: ") + strerror(errno),
                    "check the session directory's permissions");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    const std::string owner = ReadAll(fd_);
    ::close(fd_);
    if (e == EWOULDBLOCK)
      throw UserError(session_dir,
                      "the session is in use by " + (owner.empty() ? "another process" : owner),
                      "wait for it to finish or stop it (`acqctl abort`); two processes must "
                      "never write one session");
    throw UserError(path_, std::string("cannot lock the session: ") + strerror(e));
  }
  // Ours now. Whoever the file still names had gone without removing it (kill -9, power cut).
  stale_ = ReadAll(fd_);
  char started[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(started, sizeof started, "%Y-%m-%dT%H:%M:%S", std::localtime(&now));
  const std::string me = program + " pid " + std::to_string(::getpid()) + " on host " + HostName() +
                         " since " + started + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, me.data(), me.size(), 0) != ssize_t(me.size()))
    throw UserError(path_, "cannot write the session's lock", "is the disk full?");
}

SessionLock::~SessionLock() {
  // Emptied, not removed: removing it would let a third process lock a new file while a second
  // still waits on the old one's inode.
  (void)!::ftruncate(fd_, 0);
  ::close(fd_);
}

}  // namespace acq
