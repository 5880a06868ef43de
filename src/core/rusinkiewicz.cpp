#include "core/rusinkiewicz.h"

#include <Eigen/Geometry>
#include <cmath>

namespace acq {
namespace {

// Below this the half vector is the normal to within rounding and its azimuth is noise.
constexpr double kPoleTolerance = 1e-12;

}  // namespace

Eigen::Vector3d SphericalDirection(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

double ZenithOf(const Eigen::Vector3d& v) {
  return std::atan2(std::hypot(v.x(), v.y()), v.z());
}

Eigen::Vector3d DifferenceVector(double theta_d, double phi_d) {
  return SphericalDirection(theta_d, phi_d);
}

namespace {

RusinkiewiczAngles Convert(const Eigen::Vector3d& in, const Eigen::Vector3d& out, bool phi_h) {
  const Eigen::Vector3d half = (in + out).normalized();
  // Unit vectors: sqrt is exact enough here, and hypot's overflow guard costs.
  const double sin_h = std::sqrt(half.x() * half.x() + half.y() * half.y()), cos_h = half.z();
  RusinkiewiczAngles a;
  a.theta_h = std::atan2(sin_h, cos_h);
  // At theta_h = 0 phi_h is undefined and phi_d is measured from it; the convention is
  // phi_h = 0, so phi_d is the azimuth of w_i in the surface frame.
  const bool pole = sin_h < kPoleTolerance;
  a.phi_h = pole || !phi_h ? 0.0 : std::atan2(half.y(), half.x());
  const double cos_p = pole ? 1.0 : half.x() / sin_h, sin_p = pole ? 0.0 : half.y() / sin_h;
  // Rotate w_i into the half-vector frame: -phi_h about the normal, then -theta_h about y. The
  // cosines and sines come from the half vector itself; no trigonometric calls.
  const double x1 = cos_p * in.x() + sin_p * in.y();
  const double y1 = -sin_p * in.x() + cos_p * in.y();
  const Eigen::Vector3d diff(cos_h * x1 - sin_h * in.z(), y1, sin_h * x1 + cos_h * in.z());
  a.theta_d = std::atan2(std::sqrt(diff.x() * diff.x() + diff.y() * diff.y()), diff.z());
  a.phi_d = std::atan2(diff.y(), diff.x());
  return a;
}

}  // namespace

RusinkiewiczAngles RusinkiewiczFromDirections(const Eigen::Vector3d& in,
                                              const Eigen::Vector3d& out) {
  return Convert(in, out, true);
}

RusinkiewiczAngles IsotropicAnglesFromDirections(const Eigen::Vector3d& in,
                                                 const Eigen::Vector3d& out) {
  return Convert(in, out, false);
}

DirectionPair DirectionsFromRusinkiewicz(const RusinkiewiczAngles& a) {
  const Eigen::Matrix3d world_from_half = (Eigen::AngleAxisd(a.phi_h, Eigen::Vector3d::UnitZ()) *
                                           Eigen::AngleAxisd(a.theta_h, Eigen::Vector3d::UnitY()))
                                              .toRotationMatrix();
  const Eigen::Vector3d diff = DifferenceVector(a.theta_d, a.phi_d);
  // In the half frame the half vector is z; w_o is w_i reflected about it.
  const Eigen::Vector3d reflected(-diff.x(), -diff.y(), diff.z());
  return {world_from_half * diff, world_from_half * reflected};
}

bool AboveHorizon(const DirectionPair& d) {
  return d.in.z() > 0.0 && d.out.z() > 0.0;
}

}  // namespace acq
