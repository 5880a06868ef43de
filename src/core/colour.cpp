#include "core/colour.h"

#include <algorithm>
#include <cmath>

namespace acq {
namespace {

constexpr double kPi = 3.14159265358979323846;

double Degrees(double radians) {
  return radians * 180 / kPi;
}
double Radians(double degrees) {
  return degrees * kPi / 180;
}

// CIELAB's f(t), with its linear segment near black.
double LabF(double t) {
  constexpr double d = 6.0 / 29;
  return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29;
}

// Hue angle in degrees [0, 360); 0 for a neutral colour, as Sharma et al. specify.
double HueDeg(double b, double a) {
  if (a == 0 && b == 0) return 0;
  const double h = Degrees(std::atan2(b, a));
  return h < 0 ? h + 360 : h;
}

}  // namespace

Lab LabFromLinearRec709(const std::array<double, 3>& rgb) {
  const double r = rgb[0], g = rgb[1], b = rgb[2];
  // XYZ with the white (1, 1, 1) at Y = 1; the D65 white point of the same matrix.
  const double X = 0.4124 * r + 0.3576 * g + 0.1805 * b;
  const double Y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
  const double Z = 0.0193 * r + 0.1192 * g + 0.9505 * b;
  const double fx = LabF(X / 0.9505), fy = LabF(Y / 1.0), fz = LabF(Z / 1.089);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double DeltaE2000(const Lab& x, const Lab& y) {
  const double c1 = std::hypot(x.a, x.b), c2 = std::hypot(y.a, y.b);
  const double c_mean7 = std::pow((c1 + c2) / 2, 7);
  const double g = 0.5 * (1 - std::sqrt(c_mean7 / (c_mean7 + std::pow(25.0, 7))));
  const double a1 = (1 + g) * x.a, a2 = (1 + g) * y.a;
  const double cp1 = std::hypot(a1, x.b), cp2 = std::hypot(a2, y.b);
  const double hp1 = HueDeg(x.b, a1), hp2 = HueDeg(y.b, a2);
  // Differences: the hue's the short way round, none where either colour is neutral.
  const double dL = y.L - x.L, dC = cp2 - cp1;
  double dh = 0;
  if (cp1 * cp2 != 0) {
    dh = hp2 - hp1;
    if (dh > 180) dh -= 360;
    if (dh < -180) dh += 360;
  }
  const double dH = 2 * std::sqrt(cp1 * cp2) * std::sin(Radians(dh / 2));
  // Means: the hue's on the short arc, their sum where either is neutral.
  const double L_mean = (x.L + y.L) / 2, cp_mean = (cp1 + cp2) / 2;
  double hp_mean = hp1 + hp2;
  if (cp1 * cp2 != 0) {
    if (std::abs(hp1 - hp2) <= 180)
      hp_mean /= 2;
    else
      hp_mean = hp_mean < 360 ? (hp_mean + 360) / 2 : (hp_mean - 360) / 2;
  }
  const double t =
      1 - 0.17 * std::cos(Radians(hp_mean - 30)) + 0.24 * std::cos(Radians(2 * hp_mean)) +
      0.32 * std::cos(Radians(3 * hp_mean + 6)) - 0.20 * std::cos(Radians(4 * hp_mean - 63));
  const double d_theta = 30 * std::exp(-std::pow((hp_mean - 275) / 25, 2));
  const double cp_mean7 = std::pow(cp_mean, 7);
  const double r_c = 2 * std::sqrt(cp_mean7 / (cp_mean7 + std::pow(25.0, 7)));
  const double l50 = (L_mean - 50) * (L_mean - 50);
  const double s_l = 1 + 0.015 * l50 / std::sqrt(20 + l50);
  const double s_c = 1 + 0.045 * cp_mean;
  const double s_h = 1 + 0.015 * cp_mean * t;
  const double r_t = -std::sin(Radians(2 * d_theta)) * r_c;
  const double l = dL / s_l, c = dC / s_c, h = dH / s_h;
  return std::sqrt(l * l + c * c + h * h + r_t * c * h);
}

double SrgbEncode(double linear) {
  const double l = std::clamp(linear, 0.0, 1.0);
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

}  // namespace acq
