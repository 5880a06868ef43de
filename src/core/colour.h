// Colour conventions (docs/architecture.md, "Conventions"; docs/colour.md): RGB is linear
// Rec. 709 everywhere (MERL's channels, the basis, the maps), and a mono sensor records its
// luminance. Colour differences are CIEDE2000 in CIELAB under D65, the white of Rec. 709.
#pragma once

#include <array>

namespace acq {

// Rec. 709 / sRGB luminance weights of linear R, G, B.
inline constexpr std::array<double, 3> kRec709Luminance = {0.2126, 0.7152, 0.0722};

struct Lab {
  double L = 0, a = 0, b = 0;
};

// Linear Rec. 709 RGB (white 1, 1, 1 = Y 1) to CIELAB relative to that white (D65), the sRGB
// standard's matrix (IEC 61966-2-1).
Lab LabFromLinearRec709(const std::array<double, 3>& rgb);

// CIEDE2000 colour difference (CIE 142-2001; kL = kC = kH = 1), as Sharma, Wu and Dalal (2005)
// give it (their 34 published test pairs: tests/test_colour.cpp).
double DeltaE2000(const Lab& x, const Lab& y);

// The sRGB transfer function of a linear value in [0, 1] (clamped), for PNGs.
double SrgbEncode(double linear);

}  // namespace acq
