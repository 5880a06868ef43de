#include "hw/frame_file.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/angles.h"
#include "core/error.h"
#include "io/float_planes_exr.h"

namespace acq {
namespace {

constexpr const char* kFormat = "acq-frame-1";

std::string Text(double v) {
  char s[64];
  std::snprintf(s, sizeof s, "%.17g", v);
  return s;
}

}  // namespace

void WriteFrameExr(const std::string& path, const Frame& frame,
                   const std::map<std::string, std::string>& extra) {
  FloatPlanes image;
  image.width = frame.width;
  image.height = frame.height;
  image.planes["counts"].assign(frame.pixels.begin(), frame.pixels.end());
  image.attributes = extra;
  image.attributes["acqFormat"] = kFormat;
  image.attributes["exposure_us"] = Text(frame.exposure_us);
  image.attributes["gain_db"] = Text(frame.gain_db);
  image.attributes["pixel_format"] = PixelFormatName(frame.pixel_format);
  image.attributes["frame_id"] = std::to_string(frame.frame_id);
  image.attributes["timestamp_ns"] = std::to_string(frame.timestamp_ns);
  WriteFloatPlanesExr(path, image);
}

std::string ArmAnglesAttribute(const ArmAngles& a) {
  char s[96];
  std::snprintf(s, sizeof s, "%.3f %.3f %.3f %.3f", RadToDeg(a.light_theta), RadToDeg(a.light_phi),
                RadToDeg(a.camera_theta), RadToDeg(a.camera_phi));
  return s;
}

ArmAngles ParseArmAnglesAttribute(const std::string& text, const std::string& where) {
  std::istringstream in(text);
  double a[4];
  for (double& v : a)
    if (!(in >> v)) throw UserError(where, "no arm angles recorded with the frame");
  return {DegToRad(a[0]), DegToRad(a[1]), DegToRad(a[2]), DegToRad(a[3])};
}

Frame ReadFrameExr(const std::string& path, std::map<std::string, std::string>* attributes) {
  const FloatPlanes image = ReadFloatPlanesExr(path);
  auto attribute = [&](const char* name) {
    const auto it = image.attributes.find(name);
    if (it == image.attributes.end())
      throw UserError(path, std::string("not a frame file: no '") + name + "' attribute",
                      "frames are written by acqd into the session's frames/ folder");
    return it->second;
  };
  if (attribute("acqFormat") != kFormat)
    throw UserError(path, "not a frame file (acqFormat " + attribute("acqFormat") + ")");
  Frame f;
  f.width = image.width;
  f.height = image.height;
  f.pixel_format = ParsePixelFormat(attribute("pixel_format"), path);
  f.exposure_us = std::stod(attribute("exposure_us"));
  f.gain_db = std::stod(attribute("gain_db"));
  f.frame_id = std::stoull(attribute("frame_id"));
  f.timestamp_ns = std::stoull(attribute("timestamp_ns"));
  const std::vector<float>& counts = image.Plane("counts", path);
  f.pixels.reserve(counts.size());
  for (float v : counts) f.pixels.push_back(std::uint16_t(std::lround(v)));
  if (attributes) *attributes = image.attributes;
  return f;
}

}  // namespace acq
