#include "brdf/basis_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include "brdf/log_mapping.h"
#include "core/error.h"

namespace acq {
namespace {

constexpr char kMagic[8] = {'A', 'C', 'Q', 'B', 'A', 'S', 'I', 'S'};
constexpr std::uint64_t kAlign = 4096;

// Little-endian on disk; the fields are naturally aligned so the struct has no padding.
struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t header_bytes;
  std::uint32_t grid[3];  // theta_h, theta_d, phi_d
  std::uint32_t components;
  std::uint32_t training_rows;
  std::uint32_t valid_bins;
  double eps;
  double cos_weight_min;
  std::uint64_t offset_valid, offset_ref, offset_mean, offset_singular, offset_q;
  std::uint64_t offset_settings, settings_bytes;
  std::uint64_t file_bytes;
  std::uint32_t crc32;  // over the whole file with this field taken as 0
  std::uint32_t reserved;
};
static_assert(sizeof(Header) == 128, "Header layout is part of the file format");
static_assert(std::endian::native == std::endian::little, "the format is little-endian");

std::uint64_t AlignUp(std::uint64_t x) {
  return (x + kAlign - 1) / kAlign * kAlign;
}

// zlib's crc32 takes uInt lengths; feed it in chunks.
std::uint32_t CrcUpdate(std::uint32_t crc, const unsigned char* p, std::size_t n) {
  uLong c = crc;
  while (n > 0) {
    const uInt chunk = uInt(std::min<std::size_t>(n, 1u << 30));
    c = crc32(c, p, chunk);
    p += chunk;
    n -= chunk;
  }
  return std::uint32_t(c);
}

// CRC of a whole file image with the header's checksum field taken as zero.
std::uint32_t FileCrc(const unsigned char* data, std::size_t bytes) {
  const std::size_t field = offsetof(Header, crc32);
  const unsigned char zeros[4] = {0, 0, 0, 0};
  std::uint32_t crc = CrcUpdate(0, data, field);
  crc = CrcUpdate(crc, zeros, 4);
  return CrcUpdate(crc, data + field + 4, bytes - field - 4);
}

// Streams sections to disk at their offsets, zero-padding between them, and keeps the CRC.
class SectionWriter {
 public:
  SectionWriter(const std::string& path, const std::string& final_path)
      : f_(path, std::ios::binary | std::ios::trunc), final_path_(final_path) {
    if (!f_)
      throw UserError(final_path, "cannot create file", "check the folder exists and is writable");
  }
  void Put(std::uint64_t offset, const void* src, std::size_t n) {
    static const std::vector<unsigned char> zeros(kAlign, 0);
    while (pos_ < offset) {
      const std::size_t pad = std::min<std::uint64_t>(offset - pos_, kAlign);
      Raw(zeros.data(), pad);
    }
    Raw(static_cast<const unsigned char*>(src), n);
  }
  std::uint32_t crc() const { return crc_; }
  std::ofstream& stream() { return f_; }

 private:
  void Raw(const unsigned char* p, std::size_t n) {
    f_.write(reinterpret_cast<const char*>(p), std::streamsize(n));
    if (!f_) throw UserError(final_path_, "write failed", "check free disk space");
    crc_ = CrcUpdate(crc_, p, n);
    pos_ += n;
  }
  std::ofstream f_;
  std::string final_path_;
  std::uint64_t pos_ = 0;
  std::uint32_t crc_ = 0;
};

}  // namespace

// Every section the header names lies inside the file, after the header, in order, aligned
// for its type, with counts a basis can have: checked before any pointer is made from them
// (issue 22: a crafted header must be an error, not a read outside the mapping), whether or not
// the checksum is verified.
static void CheckSections(const Header& h, const std::string& path, const std::string& rebuild) {
  const std::uint64_t p = merl::kBins;
  if (h.components < 1 || h.components > 4096 || h.training_rows < h.components ||
      h.training_rows > (1u << 20))
    throw UserError(path,
                    "header holds " + std::to_string(h.components) + " components of " +
                        std::to_string(h.training_rows) + " training rows: not a basis",
                    rebuild);
  struct Section {
    const char* name;
    std::uint64_t offset, bytes, align;
  };
  const Section sections[] = {
      {"valid", h.offset_valid, p, 1},
      {"ref", h.offset_ref, 4 * p, 4},
      {"mean", h.offset_mean, 4 * p, 4},
      {"singular", h.offset_singular, 8 * std::uint64_t(h.training_rows), 8},
      {"q", h.offset_q, 4 * p * h.components, 4},
      {"settings", h.offset_settings, h.settings_bytes, 1}};
  std::uint64_t end = sizeof(Header);
  for (const Section& s : sections) {
    if (s.offset < end || s.offset % s.align != 0 || s.bytes > h.file_bytes ||
        s.offset > h.file_bytes - s.bytes)
      throw UserError(path,
                      std::string("header's ") + s.name + " section (offset " +
                          std::to_string(s.offset) + ", " + std::to_string(s.bytes) +
                          " bytes) does not lie inside the file in order",
                      "the file is corrupt or not a basis; " + rebuild);
    end = s.offset + s.bytes;
  }
}

void WriteBasisFile(const BasisView& basis, const std::string& path) {
  Header h{};
  std::memcpy(h.magic, kMagic, 8);
  h.version = kBasisFormatVersion;
  h.header_bytes = sizeof(Header);
  h.grid[0] = merl::kThetaH;
  h.grid[1] = merl::kThetaD;
  h.grid[2] = merl::kPhiD;
  h.components = std::uint32_t(basis.components);
  h.training_rows = std::uint32_t(basis.training_rows);
  h.valid_bins = std::uint32_t(std::count(basis.valid, basis.valid + merl::kBins, 1));
  h.eps = kLogMappingEps;
  h.cos_weight_min = merl::kCosWeightMin;
  const std::uint64_t p = merl::kBins;
  h.offset_valid = kAlign;
  h.offset_ref = AlignUp(h.offset_valid + p);
  h.offset_mean = AlignUp(h.offset_ref + 4 * p);
  h.offset_singular = AlignUp(h.offset_mean + 4 * p);
  h.offset_q = AlignUp(h.offset_singular + 8 * std::uint64_t(basis.training_rows));
  h.offset_settings = AlignUp(h.offset_q + 4 * p * basis.components);
  h.settings_bytes = basis.settings.size();
  h.file_bytes = h.offset_settings + h.settings_bytes;

  // Write to a temporary name and rename, so a crash never leaves a half-written basis.
  // The header goes first with a zero checksum (which is what the CRC covers), then is
  // rewritten in place once the CRC of the whole file is known.
  const std::string tmp = path + ".partial";
  {
    SectionWriter w(tmp, path);
    w.Put(0, &h, sizeof h);
    w.Put(h.offset_valid, basis.valid, p);
    w.Put(h.offset_ref, basis.ref, 4 * p);
    w.Put(h.offset_mean, basis.mean, 4 * p);
    w.Put(h.offset_singular, basis.singular_values.data(), 8 * basis.singular_values.size());
    w.Put(h.offset_q, basis.q, 4 * p * basis.components);
    w.Put(h.offset_settings, basis.settings.data(), basis.settings.size());
    h.crc32 = w.crc();
    w.stream().seekp(0);
    w.stream().write(reinterpret_cast<const char*>(&h), sizeof h);
    if (!w.stream()) throw UserError(path, "write failed", "check free disk space");
  }
  std::filesystem::rename(tmp, path);
}

MappedBasis::MappedBasis(MappedBasis&& o) noexcept
    : data_(o.data_),
      bytes_(o.bytes_),
      checksum_(o.checksum_),
      version_(o.version_),
      view_(o.view_) {
  o.data_ = nullptr;
  o.bytes_ = 0;
}

MappedBasis::~MappedBasis() {
  if (data_) munmap(data_, bytes_);
}

MappedBasis MappedBasis::Open(const std::string& path, bool verify_checksum) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw UserError(path, "cannot open basis file", "build one with `acq basis build`");
  struct stat st {};
  fstat(fd, &st);
  const std::size_t bytes = std::size_t(st.st_size);
  if (bytes < sizeof(Header)) {
    ::close(fd);
    throw UserError(path, "too short to be a basis file (" + std::to_string(bytes) + " bytes)",
                    "rebuild it with `acq basis build`");
  }
  void* data = mmap(nullptr, bytes, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (data == MAP_FAILED) throw UserError(path, "cannot memory-map the file");
  MappedBasis b;
  b.data_ = data;
  b.bytes_ = bytes;  // from here on the destructor unmaps, also when we throw below

  Header h;
  std::memcpy(&h, data, sizeof h);
  const std::string rebuild = "rebuild it with `acq basis build`";
  if (std::memcmp(h.magic, kMagic, 8) != 0)
    throw UserError(path, "not an acq basis file (wrong magic)", rebuild);
  if (h.version != kBasisFormatVersion)
    throw UserError(path,
                    "basis format version " + std::to_string(h.version) + ", this build reads " +
                        std::to_string(kBasisFormatVersion),
                    rebuild);
  if (h.file_bytes != bytes)
    throw UserError(path,
                    "file is " + std::to_string(bytes) + " bytes, its header says " +
                        std::to_string(h.file_bytes),
                    "the file is truncated; " + rebuild);
  if (h.grid[0] != merl::kThetaH || h.grid[1] != merl::kThetaD || h.grid[2] != merl::kPhiD)
    throw UserError(path, "basis is not on the 90 x 90 x 180 MERL grid", rebuild);
  CheckSections(h, path, rebuild);
  const auto* base = static_cast<const unsigned char*>(data);
  if (verify_checksum && FileCrc(base, bytes) != h.crc32)
    throw UserError(path, "checksum mismatch: the file is corrupt", rebuild);
  b.checksum_ = h.crc32;
  b.version_ = h.version;
  b.view_.components = int(h.components);
  b.view_.training_rows = int(h.training_rows);
  b.view_.valid = base + h.offset_valid;
  b.view_.ref = reinterpret_cast<const float*>(base + h.offset_ref);
  b.view_.mean = reinterpret_cast<const float*>(base + h.offset_mean);
  b.view_.q = reinterpret_cast<const float*>(base + h.offset_q);
  b.view_.singular_values = {reinterpret_cast<const double*>(base + h.offset_singular),
                             h.training_rows};
  b.view_.settings = {reinterpret_cast<const char*>(base + h.offset_settings), h.settings_bytes};
  return b;
}

}  // namespace acq
