// SHA-256 (FIPS 180-4), for the checksums of session files: a frame recorded in the catalog is
// verified on resume, so a file cut short by a crash or changed on disk is never taken as done.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace acq {

class Sha256 {
 public:
  Sha256();
  void Update(const void* data, std::size_t n);
  std::string HexDigest();  // finishes; the object is spent afterwards

 private:
  void Block(const std::uint8_t* p);
  std::uint32_t h_[8];
  std::uint8_t buffer_[64];
  std::size_t buffered_ = 0;
  std::uint64_t length_ = 0;
};

// The digest of a file's bytes; throws UserError naming the file when it cannot be read.
std::string Sha256OfFile(const std::string& path);

}  // namespace acq
