// Colour conventions (docs/architecture.md, "Conventions"): RGB is linear Rec. 709 everywhere
// (MERL's channels, the basis, the maps), and a mono sensor records its luminance.
#pragma once

#include <array>

namespace acq {

// Rec. 709 / sRGB luminance weights of linear R, G, B.
inline constexpr std::array<double, 3> kRec709Luminance = {0.2126, 0.7152, 0.0722};

}  // namespace acq
