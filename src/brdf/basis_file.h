// The basis file (docs/basis-format.md): versioned, checksummed (CRC-32 of everything but the
// checksum field), sections aligned to 4096 bytes so the file is used in place through mmap.
#pragma once

#include <cstdint>
#include <string>

#include "brdf/basis.h"

namespace acq {

constexpr std::uint32_t kBasisFormatVersion = 1;

void WriteBasisFile(const BasisView& basis, const std::string& path);

// A read-only memory map of a basis file. Move-only; unmaps on destruction.
class MappedBasis {
 public:
  // Throws UserError naming the file on a wrong magic, version, size, grid or checksum.
  // verify_checksum = false skips the full read the CRC needs (for quick `info`).
  static MappedBasis Open(const std::string& path, bool verify_checksum = true);
  MappedBasis(MappedBasis&& other) noexcept;
  MappedBasis& operator=(MappedBasis&&) = delete;
  ~MappedBasis();

  const BasisView& View() const { return view_; }
  std::uint32_t Checksum() const { return checksum_; }
  std::uint32_t Version() const { return version_; }
  std::size_t FileBytes() const { return bytes_; }

 private:
  MappedBasis() = default;
  void* data_ = nullptr;
  std::size_t bytes_ = 0;
  std::uint32_t checksum_ = 0, version_ = 0;
  BasisView view_;
};

}  // namespace acq
