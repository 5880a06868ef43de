#include "hw/camera.h"

#include <cmath>

#include "core/error.h"

namespace acq {

const char* PixelFormatName(PixelFormat format) {
  switch (format) {
    case PixelFormat::kMono8:
      return "Mono8";
    case PixelFormat::kMono12:
      return "Mono12";
    case PixelFormat::kMono16:
      return "Mono16";
  }
  return "?";
}

PixelFormat ParsePixelFormat(const std::string& name, const std::string& where) {
  for (PixelFormat f : {PixelFormat::kMono8, PixelFormat::kMono12, PixelFormat::kMono16})
    if (name == PixelFormatName(f)) return f;
  throw UserError(where, "unknown pixel format '" + name + "'", "use Mono8, Mono12 or Mono16");
}

int MaxValue(PixelFormat format) {
  switch (format) {
    case PixelFormat::kMono8:
      return 255;
    case PixelFormat::kMono12:
      return 4095;
    case PixelFormat::kMono16:
      return 65535;
  }
  return 0;
}

void CameraSettings::Check(const std::string& where) const {
  if (!(exposure_us > 0 && std::isfinite(exposure_us)))
    throw UserError(where, "exposure must be a positive number of microseconds");
  if (!(gain_db >= 0 && gain_db <= 48)) throw UserError(where, "gain must be in [0, 48] dB");
  if (width < 0 || height < 0 || (width == 0) != (height == 0))
    throw UserError(where, "give both width and height, or neither (the camera's region)");
}

}  // namespace acq
