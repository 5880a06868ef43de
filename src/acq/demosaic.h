// Demosaicing (issue 16): a colour camera's HDR mosaic, merged photosite by photosite
// (MergeBracket), into camera R, G and B at every pixel. The merge goes first, so that a
// photosite's saturation and noise floor are judged on its own counts in each exposure and the
// interpolation runs once per pose on linear radiance; docs/colour.md has the measured choice.
//
// Methods, both linear in the radiance (OpenCV's Bayer conversions take 8- and 16-bit counts
// only, not an HDR image's floats):
//   bilinear  each missing channel the mean of the nearest photosites that have it (3 x 3);
//   malvar    Malvar, He and Cutler (ICASSP 2004): bilinear corrected by the known channel's
//             Laplacian, 5 x 5 kernels; sharper at edges, can overshoot, clamped at 0.
// A pixel is flagged (saturated or dark) when any photosite its value came from was.
#pragma once

#include <optional>
#include <string>

#include "acq/hdr.h"

namespace acq {

enum class DemosaicMethod { kBilinear, kMalvar };
const char* DemosaicMethodName(DemosaicMethod method);  // "bilinear", "malvar"
std::optional<DemosaicMethod> ParseDemosaicMethod(const std::string& name);
inline constexpr DemosaicMethod kDefaultDemosaic = DemosaicMethod::kMalvar;

// A mosaic (cfa != kNone, one plane) into three planes; an image without a filter is returned
// as it is. Throws std::logic_error on an image that is neither.
HdrImage Demosaic(HdrImage mosaic, DemosaicMethod method = kDefaultDemosaic);

}  // namespace acq
