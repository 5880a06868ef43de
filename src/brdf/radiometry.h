// From measured radiance to BRDF values (Yu et al. Sec. 4: "the same procedure is also
// performed on a spectralon board to calibrate the light intensity").
//
// A surface lit with irradiance E (perpendicular to the light) at incidence theta_i reflects
// L = rho E cos(theta_i). A Spectralon board, Lambertian with reflectance R (0.99), imaged in
// the same view under the same light reflects L_s = (R / pi) E cos(theta_i), so
//   rho = R L / (pi L_s)
// with no need to know the light. Without a Spectralon capture, a point light of radiant
// intensity I at distance r gives E = I / r^2, so rho = L r^2 / (I cos(theta_i)).
// Any unusable input (saturated, below the noise floor, no light) gives NaN: the observation is
// dropped for that pixel (PixelObservations), never turned into a number.
#pragma once

namespace acq {

constexpr double kSpectralonReflectance = 0.99;

double BrdfFromSpectralon(double radiance, double spectralon_radiance,
                          double reflectance = kSpectralonReflectance);
double BrdfFromPointLight(double radiance, double intensity, double distance, double cos_theta_i);

}  // namespace acq
