#include "core/gantry_geometry.h"

#include <algorithm>
#include <cmath>

#include "core/angles.h"
#include "core/error.h"

namespace acq {
namespace {

double Azimuth(const Eigen::Vector3d& v) {
  return std::atan2(v.y(), v.x());
}

std::string Deg(double rad) {
  return DegString(rad, 3);
}

}  // namespace

ArmAngles ArmAnglesFor(const RusinkiewiczAngles& a) {
  DirectionPair d = DirectionsFromRusinkiewicz(a);
  if (d.out.z() < d.in.z()) std::swap(d.in, d.out);  // camera: the smaller zenith
  return {ZenithOf(d.in), Azimuth(d.in), ZenithOf(d.out), Azimuth(d.out)};
}

DirectionPair DirectionsOf(const ArmAngles& arms) {
  return {SphericalDirection(arms.light_theta, arms.light_phi),
          SphericalDirection(arms.camera_theta, arms.camera_phi)};
}

void DirectionConstraints::Check() const {
  auto in_range = [](double v, double lo, double hi, const char* flag) {
    if (!(v >= lo && v <= hi))
      throw UserError(flag,
                      "must be between " + Deg(lo) + " and " + Deg(hi) + " degrees, got " + Deg(v));
  };
  in_range(max_camera_zenith, DegToRad(1), DegToRad(90), "--max-camera-zenith-deg");
  in_range(max_light_zenith, DegToRad(1), DegToRad(90), "--max-light-zenith-deg");
  in_range(min_separation, 0, DegToRad(170), "--min-separation-deg");
}

std::string DirectionConstraints::Violation(const ArmAngles& arms) const {
  const DirectionPair d = DirectionsOf(arms);
  if (!(d.in.z() > 0 && d.out.z() > 0))
    return "below the horizon (light zenith " + Deg(arms.light_theta) + ", camera zenith " +
           Deg(arms.camera_theta) + " deg)";
  if (!enabled) return {};
  if (arms.camera_theta > max_camera_zenith)
    return "camera zenith " + Deg(arms.camera_theta) + " deg exceeds the limit of " +
           Deg(max_camera_zenith);
  if (arms.light_theta > max_light_zenith)
    return "light zenith " + Deg(arms.light_theta) + " deg is beyond the light arm's reach of " +
           Deg(max_light_zenith);
  const double separation = std::acos(std::clamp(d.in.dot(d.out), -1.0, 1.0));
  if (separation < min_separation)
    return "light and camera only " + Deg(separation) + " deg apart, the arms need " +
           Deg(min_separation);
  return {};
}

double NearFieldGeometry::SampleSizeForFov(double fov, double camera_distance_mm) {
  return 2.0 * camera_distance_mm * std::tan(fov / 2);
}

std::vector<Eigen::Vector2d> NearFieldGeometry::Positions(int grid, bool to_edges) const {
  std::vector<Eigen::Vector2d> out;
  if (sample_size_mm <= 0 || grid <= 1) return {Eigen::Vector2d::Zero()};
  auto coordinate = [&](int i) {
    const double u = to_edges ? double(i) / (grid - 1) : (i + 0.5) / grid;
    return (u - 0.5) * sample_size_mm;
  };
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) out.emplace_back(coordinate(i), coordinate(j));
  return out;
}

DirectionPair NearFieldGeometry::DirectionsAt(const DirectionPair& far,
                                              const Eigen::Vector2d& p_in_sample) const {
  const Eigen::Vector3d p(p_in_sample.x(), p_in_sample.y(), 0.0);
  return {(light_distance_mm * far.in - p).normalized(),
          (camera_distance_mm * far.out - p).normalized()};
}

}  // namespace acq
