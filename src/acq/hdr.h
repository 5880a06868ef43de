// HDR (issue 6): a bracket of exposures at one pose merged into one linear radiance image.
//
// Each frame's count v is turned into counts per microsecond at unit gain,
// (v - black) / (exposure_us * gain), and the frames are averaged with per-pixel weights: a
// frame's value is used only where it is neither saturated nor in the noise floor, weighted by
// exposure x gain (for shot-noise-limited pixels the variance of that estimate falls as
// 1 / (exposure x gain), so this is the inverse-variance weight). A pixel saturated in every
// frame, or dark in every frame, keeps the best value it has and is flagged.
#pragma once

#include <cstdint>
#include <vector>

#include "hw/camera.h"

namespace acq {

struct HdrOptions {
  double saturation_fraction = 0.95;  // counts at or above this share of full scale: saturated
  double black_level_dn = 0;          // the sensor's offset, in counts
  double noise_floor_dn = 16;         // counts above black below which a value is not used
  void Check() const;                 // throws UserError
};

enum HdrFlag : std::uint8_t { kHdrOk = 0, kHdrSaturated = 1, kHdrDark = 2 };

struct HdrImage {
  int width = 0, height = 0;
  // A colour camera's bracket is merged photosite by photosite: `cfa` is its filter while the
  // image is that mosaic (one plane), and kNone once demosaiced (acq/demosaic.h).
  Cfa cfa = Cfa::kNone;
  int channels = 1;                // 1, or 3: camera R, G, B planes one after the other
  std::vector<float> radiance;     // counts per microsecond at 0 dB, `channels` planes
  std::vector<std::uint8_t> flag;  // HdrFlag per pixel (any channel's)
  std::vector<std::uint8_t> used;  // how many frames each pixel's value came from
  const float* Plane(int channel) const {
    return radiance.data() + std::size_t(channel) * std::size_t(width) * std::size_t(height);
  }
  // One grey plane: the radiance, or the mean of the three channels (for the board detector).
  std::vector<float> Grey() const;
};

// Throws UserError when the frames differ in size or filter, or a frame has no exposure.
HdrImage MergeBracket(const std::vector<Frame>& frames, const HdrOptions& options);

struct AutoBracketOptions {
  double min_exposure_us = 20, max_exposure_us = 2e6;
  double step = 4;  // exposure ratio between frames (2 stops)
  int max_frames = 8;
  double headroom =
      0.8;  // the brightest pixel (99.99th percentile) lands at this share of full scale
  double dark_percentile = 0.01;  // the darkest pixels that must clear the noise floor 10x
};

// Exposures from the shortest that keeps the brightest pixels below saturation to the one that
// lifts the dark end above the noise floor, from probe frames (taken shorter while saturated).
std::vector<double> ChooseBracket(Camera& camera, CameraSettings settings, const HdrOptions& hdr,
                                  const AutoBracketOptions& options);

// Takes one frame per exposure (each applied and verified before its trigger).
std::vector<Frame> CaptureBracket(Camera& camera, CameraSettings settings,
                                  const std::vector<double>& exposures_us);

}  // namespace acq
