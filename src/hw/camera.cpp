#include "hw/camera.h"

#include <cmath>
#include <stdexcept>

#include "core/error.h"

namespace acq {

namespace {

struct FormatInfo {
  PixelFormat format;
  const char* name;
  int max_value;
  Cfa cfa;
};

constexpr FormatInfo kFormats[] = {
    {PixelFormat::kMono8, "Mono8", 255, Cfa::kNone},
    {PixelFormat::kMono12, "Mono12", 4095, Cfa::kNone},
    {PixelFormat::kMono16, "Mono16", 65535, Cfa::kNone},
    {PixelFormat::kBayerRG8, "BayerRG8", 255, Cfa::kRGGB},
    {PixelFormat::kBayerRG12, "BayerRG12", 4095, Cfa::kRGGB},
    {PixelFormat::kBayerRG16, "BayerRG16", 65535, Cfa::kRGGB},
    {PixelFormat::kBayerGR8, "BayerGR8", 255, Cfa::kGRBG},
    {PixelFormat::kBayerGR12, "BayerGR12", 4095, Cfa::kGRBG},
    {PixelFormat::kBayerGR16, "BayerGR16", 65535, Cfa::kGRBG},
    {PixelFormat::kBayerGB8, "BayerGB8", 255, Cfa::kGBRG},
    {PixelFormat::kBayerGB12, "BayerGB12", 4095, Cfa::kGBRG},
    {PixelFormat::kBayerGB16, "BayerGB16", 65535, Cfa::kGBRG},
    {PixelFormat::kBayerBG8, "BayerBG8", 255, Cfa::kBGGR},
    {PixelFormat::kBayerBG12, "BayerBG12", 4095, Cfa::kBGGR},
    {PixelFormat::kBayerBG16, "BayerBG16", 65535, Cfa::kBGGR},
};

const FormatInfo& InfoOf(PixelFormat format) {
  for (const FormatInfo& i : kFormats)
    if (i.format == format) return i;
  throw std::logic_error("PixelFormat missing from kFormats");
}

}  // namespace

const char* PixelFormatName(PixelFormat format) {
  return InfoOf(format).name;
}

PixelFormat ParsePixelFormat(const std::string& name, const std::string& where) {
  for (const FormatInfo& i : kFormats)
    if (name == i.name) return i.format;
  throw UserError(where, "unknown pixel format '" + name + "'",
                  "use Mono8, Mono12, Mono16, or a Bayer format such as BayerRG8, BayerRG12, "
                  "BayerRG16 (RG, GR, GB or BG: the camera's filter phase)");
}

int MaxValue(PixelFormat format) {
  return InfoOf(format).max_value;
}

Cfa CfaOf(PixelFormat format) {
  return InfoOf(format).cfa;
}

PixelFormat PixelFormatFor(Cfa cfa, int max_value) {
  for (const FormatInfo& i : kFormats)
    if (i.cfa == cfa && i.max_value == max_value) return i.format;
  throw std::logic_error("no pixel format for that filter and depth");
}

void CameraSettings::Check(const std::string& where) const {
  if (!(exposure_us > 0 && std::isfinite(exposure_us)))
    throw UserError(where, "exposure must be a positive number of microseconds");
  if (!(gain_db >= 0 && gain_db <= 48)) throw UserError(where, "gain must be in [0, 48] dB");
  if (width < 0 || height < 0 || (width == 0) != (height == 0))
    throw UserError(where, "give both width and height, or neither (the camera's region)");
}

}  // namespace acq
