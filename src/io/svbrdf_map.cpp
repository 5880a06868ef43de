#include "io/svbrdf_map.h"

#include <ImfChannelList.h>
#include <ImfChromaticities.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "core/sample_grid.h"
#include "io/exr_settings.h"

namespace acq {
namespace {

constexpr const char* kFormat = "acq-svbrdf-map 1";
constexpr const char* kRowRule = "rows to the sample's -y (core/sample_grid.h)";

const std::vector<std::string> kDiagnostics = {"valid",
                                               "observations",
                                               "condition",
                                               "residual",
                                               "group",
                                               "departure",
                                               "normal.x",
                                               "normal.y",
                                               "normal.z",
                                               "normal_status",
                                               "normal_uncertainty_deg"};
// Diagnostics a map may lack (written before they existed), with the value they read as.
float OptionalDiagnostic(const std::string& name) {
  if (name == "group") return -1.0f;
  if (name == "departure" || name == "normal.x" || name == "normal.y") return 0.0f;
  if (name == "normal.z") return 1.0f;
  if (name == "normal_status") return 0.0f;
  if (name == "normal_uncertainty_deg") return -1.0f;  // kNoNormalUncertainty: none estimated
  return std::numeric_limits<float>::quiet_NaN();
}

std::string Hex(std::uint32_t v) {
  char s[16];
  std::snprintf(s, sizeof s, "%08x", v);
  return s;
}

}  // namespace

std::vector<std::string> SvbrdfChannelNames(int k) {
  std::vector<std::string> names;
  for (const char* c : {"R", "G", "B"})
    for (int j = 0; j < k; ++j) {
      char s[16];
      std::snprintf(s, sizeof s, "%s.c%02d", c, j);
      names.push_back(s);
    }
  names.insert(names.end(), kDiagnostics.begin(), kDiagnostics.end());
  return names;
}

struct SvbrdfMapWriter::Impl {
  std::string path, partial;
  SvbrdfMapInfo info;
  std::vector<std::string> names;
  std::unique_ptr<Imf::OutputFile> file;
  int next_row = 0;
  bool finished = false;
};

SvbrdfMapWriter::SvbrdfMapWriter(const std::string& path, const SvbrdfMapInfo& info)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->partial = path + ".partial.exr";
  impl_->info = info;
  impl_->names = SvbrdfChannelNames(info.components);
  Imf::Header header(info.width, info.height);
  header.compression() = kExrCompression;
  UseExrThreads();
  for (const std::string& n : impl_->names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
  // The coefficients' colour space: linear Rec. 709 primaries and white (OpenEXR's default
  // Chromaticities), stated so that colour-managed readers need not assume it.
  Imf::addChromaticities(header, Imf::Chromaticities());
  header.insert("acqFormat", Imf::StringAttribute(kFormat));
  header.insert("acqBasis", Imf::StringAttribute(info.basis));
  header.insert("acqBasisCrc32", Imf::StringAttribute(Hex(info.basis_crc32)));
  header.insert("acqComponents", Imf::IntAttribute(info.components));
  header.insert("acqEta", Imf::DoubleAttribute(info.eta));
  header.insert("acqRowLookup", Imf::StringAttribute(info.lookup));
  header.insert("acqCameraModel", Imf::StringAttribute(info.camera_model));
  header.insert("acqPixelSizeMm", Imf::DoubleAttribute(info.pixel_size_mm));
  if (info.pixel_spread_px > 0)
    header.insert("acqPixelSpreadPx", Imf::DoubleAttribute(info.pixel_spread_px));
  header.insert("acqSource", Imf::StringAttribute(info.source));
  header.insert("acqMethod", Imf::StringAttribute(info.method));
  if (!info.model.empty()) header.insert("acqModel", Imf::StringAttribute(info.model));
  if (info.rows_to_minus_y) header.insert("acqRowRule", Imf::StringAttribute(kRowRule));
  try {
    impl_->file = std::make_unique<Imf::OutputFile>(impl_->partial.c_str(), header);
  } catch (const std::exception& e) {
    throw UserError(path, std::string("cannot create the map: ") + e.what(),
                    "check the folder exists and is writable");
  }
}

SvbrdfMapWriter::~SvbrdfMapWriter() {
  if (impl_ && !impl_->finished) {
    impl_->file.reset();
    std::error_code ec;
    std::filesystem::remove(impl_->partial, ec);
  }
}

void SvbrdfMapWriter::WriteRows(int rows, const std::vector<const float*>& planes) {
  const int w = impl_->info.width;
  if (planes.size() != impl_->names.size() || impl_->next_row + rows > impl_->info.height)
    throw std::logic_error("SvbrdfMapWriter::WriteRows: wrong planes or too many rows");
  Imf::FrameBuffer fb;
  const std::size_t row_stride = sizeof(float) * std::size_t(w);
  for (std::size_t c = 0; c < planes.size(); ++c) {
    // OpenEXR addresses pixel (x, y) as base + x * xStride + y * yStride with absolute y: shift
    // the base so that this band's first row is row next_row.
    char* base = reinterpret_cast<char*>(const_cast<float*>(planes[c])) -
                 std::ptrdiff_t(impl_->next_row) * std::ptrdiff_t(row_stride);
    fb.insert(impl_->names[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), row_stride));
  }
  try {
    impl_->file->setFrameBuffer(fb);
    impl_->file->writePixels(rows);
  } catch (const std::exception& e) {
    throw UserError(impl_->path, std::string("write failed: ") + e.what(), "check free disk space");
  }
  impl_->next_row += rows;
}

void SvbrdfMapWriter::Finish() {
  if (impl_->next_row != impl_->info.height)
    throw std::logic_error("SvbrdfMapWriter::Finish before all rows were written");
  impl_->file.reset();  // flushes and closes
  std::filesystem::rename(impl_->partial, impl_->path);
  impl_->finished = true;
}

std::vector<float> SvbrdfMap::Coefficients(int x, int y, int channel) const {
  const int k = info.components;
  std::vector<float> c(k);
  const std::size_t at = std::size_t(y) * info.width + x;
  for (int j = 0; j < k; ++j) c[j] = planes[channel * k + j][at];
  return c;
}

float SvbrdfMap::Plane(const std::string& name, int x, int y) const {
  for (std::size_t i = 0; i < kDiagnostics.size(); ++i)
    if (kDiagnostics[i] == name)
      return planes[3 * info.components + i][std::size_t(y) * info.width + x];
  throw std::logic_error("no plane " + name);
}

SvbrdfMap ReadSvbrdfMap(const std::string& path) {
  try {
    UseExrThreads();
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    const auto* format = h.findTypedAttribute<Imf::StringAttribute>("acqFormat");
    if (!format || format->value() != kFormat)
      throw UserError(path, "not an acq SVBRDF map (no acqFormat attribute)",
                      "give a map written by `acq reconstruct`");
    SvbrdfMap map;
    const Imath::Box2i dw = h.dataWindow();
    map.info.width = dw.max.x - dw.min.x + 1;
    map.info.height = dw.max.y - dw.min.y + 1;
    map.info.components = h.typedAttribute<Imf::IntAttribute>("acqComponents").value();
    map.info.eta = h.typedAttribute<Imf::DoubleAttribute>("acqEta").value();
    map.info.lookup = h.typedAttribute<Imf::StringAttribute>("acqRowLookup").value();
    map.info.basis = h.typedAttribute<Imf::StringAttribute>("acqBasis").value();
    map.info.basis_crc32 = std::uint32_t(
        std::stoul(h.typedAttribute<Imf::StringAttribute>("acqBasisCrc32").value(), nullptr, 16));
    map.info.camera_model = h.typedAttribute<Imf::StringAttribute>("acqCameraModel").value();
    map.info.pixel_size_mm = h.typedAttribute<Imf::DoubleAttribute>("acqPixelSizeMm").value();
    map.info.source = h.typedAttribute<Imf::StringAttribute>("acqSource").value();
    if (const auto* spread = h.findTypedAttribute<Imf::DoubleAttribute>("acqPixelSpreadPx"))
      map.info.pixel_spread_px = spread->value();
    if (const auto* m = h.findTypedAttribute<Imf::StringAttribute>("acqMethod"))
      map.info.method = m->value();
    if (const auto* m = h.findTypedAttribute<Imf::StringAttribute>("acqModel"))
      map.info.model = m->value();
    const std::vector<std::string> names = SvbrdfChannelNames(map.info.components);
    const std::size_t n = std::size_t(map.info.width) * map.info.height;
    map.planes.assign(names.size(), std::vector<float>(n));
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < names.size(); ++c) {
      if (!h.channels().findChannel(names[c])) {
        const float fill = OptionalDiagnostic(names[c]);
        if (std::isnan(fill))
          throw UserError(path, "channel " + names[c] + " is missing", "the map is damaged");
        std::fill(map.planes[c].begin(), map.planes[c].end(), fill);
        continue;
      }
      char* base = reinterpret_cast<char*>(map.planes[c].data()) -
                   (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * map.info.width) *
                       std::ptrdiff_t(sizeof(float));
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                     sizeof(float) * std::size_t(map.info.width)));
    }
    file.setFrameBuffer(fb);
    if (!file.isComplete())
      throw UserError(path, "the map is incomplete (a write was interrupted)",
                      "run the reconstruction again");
    file.readPixels(dw.min.y, dw.max.y);
    map.info.rows_to_minus_y = h.findTypedAttribute<Imf::StringAttribute>("acqRowRule") != nullptr;
    if (!map.info.rows_to_minus_y && map.info.camera_model == kSyntheticCameraModel) {
      for (std::vector<float>& plane : map.planes) FlipGridRows(&plane, map.info.width);
      map.info.rows_to_minus_y = true;
    }
    return map;
  } catch (const UserError&) {
    throw;
  } catch (const std::exception& e) {
    throw UserError(path, std::string("cannot read the SVBRDF map: ") + e.what());
  }
}

}  // namespace acq
