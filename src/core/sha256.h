// SHA-256, for the checksums of session files: a frame recorded in the catalog is verified on
// resume, so a file cut short by a crash or changed on disk is never taken as done. OpenSSL's
// digest (issue 21: a maintained library, not our own; about 4x faster here than the hand-written
// one it replaced, which matters for a 386 MB basis hashed for the plan record).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace acq {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void Update(const void* data, std::size_t n);
  std::string HexDigest();  // finishes; the object is spent afterwards

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

// The digest of a file's bytes; throws UserError naming the file when it cannot be read.
std::string Sha256OfFile(const std::string& path);

}  // namespace acq
