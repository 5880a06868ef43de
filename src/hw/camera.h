// The camera as the rest of the product sees it (docs/architecture.md: one interface per hardware
// kind). Implementations: AravisCamera (any GigE Vision or USB3 Vision camera through Aravis 0.8;
// the simulated camera is one of those) and ReplayCamera (the frames of a recorded session).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/cfa.h"

namespace acq {

// The formats the driver takes: mono, and Bayer in each of the four phases (issue 16), each at 8,
// 12 and 16 bits. One table (camera.cpp) gives each its GenICam name, depth and filter.
enum class PixelFormat {
  kMono8,
  kMono12,
  kMono16,
  kBayerRG8,
  kBayerRG12,
  kBayerRG16,
  kBayerGR8,
  kBayerGR12,
  kBayerGR16,
  kBayerGB8,
  kBayerGB12,
  kBayerGB16,
  kBayerBG8,
  kBayerBG12,
  kBayerBG16,
};
const char* PixelFormatName(PixelFormat format);  // the GenICam name, "Mono16", "BayerRG12"
PixelFormat ParsePixelFormat(const std::string& name, const std::string& where);  // UserError
int MaxValue(PixelFormat format);  // 255, 4095, 65535
Cfa CfaOf(PixelFormat format);     // Cfa::kNone for mono
// The Bayer format of a filter at a depth of `max_value` (255, 4095, 65535); mono for kNone.
PixelFormat PixelFormatFor(Cfa cfa, int max_value);

struct CameraSettings {
  PixelFormat pixel_format = PixelFormat::kMono16;
  double exposure_us = 10000;
  double gain_db = 0;
  int width = 0, height = 0;                   // 0: leave the camera's region as it is
  void Check(const std::string& where) const;  // throws UserError
};

// A complete frame: counts widened to 16 bits, with the settings it was taken with.
struct Frame {
  int width = 0, height = 0;
  PixelFormat pixel_format = PixelFormat::kMono16;
  double exposure_us = 0, gain_db = 0;
  std::uint64_t frame_id = 0, timestamp_ns = 0;
  std::vector<std::uint16_t> pixels;
  int MaxValue() const { return acq::MaxValue(pixel_format); }
};

struct StreamStatistics {
  std::uint64_t completed = 0;        // frames delivered complete
  std::uint64_t incomplete = 0;       // frames that arrived with missing data or timed out
  std::uint64_t missing_packets = 0;  // as the transport counts them (GigE Vision)
  std::uint64_t resent_packets = 0;
  std::uint64_t retakes = 0;          // frames triggered again after a failure
  std::uint64_t reopens = 0;          // times control was lost and the camera reopened
  std::uint64_t stale_discarded = 0;  // frames from before a trigger, never used
};

class Camera {
 public:
  virtual ~Camera() = default;
  // Applies and verifies the settings (the exposure read back must be the one asked for);
  // throws UserError naming the camera and the setting.
  virtual void Apply(const CameraSettings& settings) = 0;
  // One complete frame taken after the call with the applied settings; retakes after
  // incomplete frames, reopens after a lost camera; throws UserError when it cannot.
  virtual Frame Grab() = 0;
  virtual StreamStatistics Statistics() const = 0;
  virtual std::string Describe() const = 0;
};

}  // namespace acq
