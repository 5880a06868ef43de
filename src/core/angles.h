// Radians inside the code; degrees only at the edges (CLI, TSV, YAML), named with _deg.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace acq {

constexpr double kPi = 3.14159265358979323846;
constexpr double DegToRad(double deg) {
  return deg * (kPi / 180.0);
}
constexpr double RadToDeg(double rad) {
  return rad * (180.0 / kPi);
}

// An angle in degrees with a fixed number of decimals, for messages to the user.
inline std::string DegString(double rad, int decimals) {
  char s[32];
  std::snprintf(s, sizeof s, "%.*f", decimals, RadToDeg(rad));
  return s;
}

}  // namespace acq
