#include "brdf/radiometry.h"

#include <cmath>
#include <limits>

#include "core/angles.h"

namespace acq {
namespace {
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double BrdfFromSpectralon(double radiance, double spectralon_radiance, double reflectance) {
  if (!std::isfinite(radiance) || !(spectralon_radiance > 0) || !(reflectance > 0)) return kNan;
  return reflectance * radiance / (kPi * spectralon_radiance);
}

double BrdfFromPointLight(double radiance, double intensity, double distance, double cos_theta_i) {
  if (!std::isfinite(radiance) || !(intensity > 0) || !(distance > 0) || !(cos_theta_i > 0))
    return kNan;
  return radiance * distance * distance / (intensity * cos_theta_i);
}

}  // namespace acq
