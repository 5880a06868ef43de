// A surface facet's frame (issue 19, per-pixel normals): the one convention the simulator, the
// normal search and the renderers share. A shading normal n is given in the sample frame (unit,
// n.z > 0); the facet frame is the sample frame turned by the shortest arc that takes n to +z,
// so its tangent x stays as near the sample's x as the tilt allows (tangent-space normals in
// docs/svbrdf-map.md are n in the sample frame, which for a flat sample is its tangent space).
// A BRDF value measured as if the sample were flat, L / (E cos theta_i) with theta_i from the
// sample's normal, is the facet's BRDF times (n . l) / l.z.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

namespace acq {

// The rotation taking sample-frame directions into the facet frame of normal n.
inline Eigen::Matrix3f FacetFromSample(const Eigen::Vector3f& n) {
  return Eigen::Quaternionf::FromTwoVectors(n, Eigen::Vector3f::UnitZ()).toRotationMatrix();
}

// The unit normal whose slope is (sx, sy): n proportional to (sx, sy, 1), tilted atan |s|
// towards the direction of s.
inline Eigen::Vector3f NormalOfSlope(float sx, float sy) {
  return Eigen::Vector3f(sx, sy, 1.0f).normalized();
}

// The angle between two unit normals, in radians (clamped: never NaN).
inline double NormalAngle(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::acos(std::clamp(double(a.dot(b)), -1.0, 1.0));
}

// A BRDF f(in, out) of the facet of normal n (facet-frame directions) as a measurement taken as
// if the sample were flat sees it at sample-frame directions in, out: f at the directions turned
// into the facet's frame, times (n . l) / l.z. Zero where the facet turns away from the light or
// hides from the camera (dark, as a camera records it) or the light lies below the sample. The
// one rule the simulator's renderer, the map's renders and the scoring share.
template <class FacetBrdf>
std::array<double, 3> SeenAsFlat(const Eigen::Vector3f& n, const Eigen::Vector3d& in,
                                 const Eigen::Vector3d& out, const FacetBrdf& f) {
  const Eigen::Matrix3d r = FacetFromSample(n).cast<double>();
  const Eigen::Vector3d fi = (r * in).normalized(), fo = (r * out).normalized();
  if (!(fi.z() > 0 && fo.z() > 0 && in.z() > 0)) return {0, 0, 0};
  std::array<double, 3> rho = f(fi, fo);
  for (double& v : rho) v *= fi.z() / in.z();
  return rho;
}

}  // namespace acq
