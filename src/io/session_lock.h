// Ownership of a session directory (issue 22): one acqd (or `acq session repair`) at a time.
// The lock is an flock(2) on <session>/acqd.lock, held for the owner's life and released by
// the kernel however it ends (kill -9 included), so a lock is never left held by the dead. The
// file names its owner (pid, host, program, start time) for the refusal a second one gets;
// a file whose owner is gone is a stale lock, taken over and said so.
#pragma once

#include <string>

namespace acq {

class SessionLock {
 public:
  // Creates the session directory if need be and takes its lock. Throws UserError naming the
  // owner when another process holds it. `program` goes into the file ("acqd", "acq").
  SessionLock(const std::string& session_dir, const std::string& program);
  ~SessionLock();
  SessionLock(const SessionLock&) = delete;
  SessionLock& operator=(const SessionLock&) = delete;

  // Non-empty when the lock was taken over from an owner that had gone (its description).
  const std::string& taken_over_from() const { return stale_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_, stale_;
  int fd_ = -1;
};

}  // namespace acq
