// HDR (issue 6): a bracket of exposures at one pose merged into one linear radiance image.
//
// Each pixel's value comes from its longest frame below saturation, turned into counts per
// microsecond at unit gain, (v - black) / (exposure_us * gain), clamped at 0. A pixel saturated
// in every frame keeps the shortest frame's value and is flagged. No value is judged by a noise
// floor: keeping a frame's value only where noise put it high biases the dark end upwards and
// drops views (before 2026-12-03 the merge averaged every frame whose value lay between a floor
// of 16 counts and saturation, weighted by exposure; through acqd the colour card's black fabric
// then came out 0.187 from the truth, 0.167 with every value averaged, floor or not, and 0.156
// with the longest frame alone; docs/camera.md, "The noise floor"). The longest frame holds
// most of the signal (the weighted mean gains at most the sum of the bracket's exposures over
// the longest, 1.33 for 2-stop steps: 15% less noise), and its value is unbiased but for the
// sensor's clip at zero counts.
#pragma once

#include <cstdint>
#include <vector>

#include "hw/camera.h"

namespace acq {

// The merge's rule, recorded in each pose's hdr file: a file merged by another rule is merged
// again rather than reused (the rule changed on 2026-12-03).
inline constexpr const char* kHdrMergeRule = "longest frame below saturation";

struct HdrOptions {
  double saturation_fraction = 0.95;  // counts at or above this share of full scale: saturated
  double black_level_dn = 0;          // the sensor's offset, in counts
  // Counts above black that the automatic bracket lifts the dark end to 10x of (ChooseBracket);
  // the merge uses every value above black.
  double noise_floor_dn = 16;
  void Check() const;  // throws UserError
};

// kHdrDark: a pixel under the noise floor in every frame, set by merges before 2026-12-03 and
// still found in their sessions' hdr/ files (treated as unusable, as then); not set any more.
enum HdrFlag : std::uint8_t { kHdrOk = 0, kHdrSaturated = 1, kHdrDark = 2 };

struct HdrImage {
  int width = 0, height = 0;
  // A colour camera's bracket is merged photosite by photosite: `cfa` is its filter while the
  // image is that mosaic (one plane), and kNone once demosaiced (acq/demosaic.h).
  Cfa cfa = Cfa::kNone;
  int channels = 1;                // 1, or 3: camera R, G, B planes one after the other
  std::vector<float> radiance;     // counts per microsecond at 0 dB, `channels` planes
  std::vector<std::uint8_t> flag;  // HdrFlag per pixel (any channel's)
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
