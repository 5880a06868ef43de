#include <catch2/catch.hpp>
#include <cmath>

#include "brdf/radiometry.h"
#include "core/angles.h"

using namespace acq;

TEST_CASE("radiance to BRDF, hand computed", "[radiometry]") {
  // A Lambertian sample of albedo 0.5 has rho = 0.5 / pi; under the same light as a 0.99
  // Spectralon its radiance is 0.5 / 0.99 of the board's.
  const double board = 3.7;  // any radiance
  CHECK(BrdfFromSpectralon(board * 0.5 / 0.99, board) == Approx(0.5 / kPi));
  // Point light: I = 2 W/sr at 0.5 m, 60 degrees incidence: E cos = 2 / 0.25 * 0.5 = 4 W/m^2;
  // a radiance of 1 W/(m^2 sr) means rho = 0.25 / sr.
  CHECK(BrdfFromPointLight(1.0, 2.0, 0.5, std::cos(DegToRad(60))) == Approx(0.25));
}

TEST_CASE("unusable inputs give NaN, never a number", "[radiometry]") {
  CHECK(std::isnan(BrdfFromSpectralon(std::nan(""), 1.0)));   // saturated pixel
  CHECK(std::isnan(BrdfFromSpectralon(1.0, 0.0)));            // board not lit
  CHECK(std::isnan(BrdfFromPointLight(1.0, 1.0, 1.0, 0.0)));  // grazing light
  CHECK(std::isnan(BrdfFromPointLight(1.0, 0.0, 1.0, 0.5)));  // light off
}
