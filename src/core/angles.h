// Radians inside the code; degrees only at the edges (CLI, TSV, YAML), named with _deg.
#pragma once

#include <cmath>

namespace acq {

constexpr double kPi = 3.14159265358979323846;
constexpr double DegToRad(double deg) {
  return deg * (kPi / 180.0);
}
constexpr double RadToDeg(double rad) {
  return rad * (180.0 / kPi);
}

}  // namespace acq
