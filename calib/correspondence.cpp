#include "calib/correspondence.h"

#include <cmath>
#include <limits>

namespace acq::calib {

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
}

Eigen::Vector3d ArmPositionInSample(double theta, double phi, double distance_mm) {
  return distance_mm * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                       std::sin(theta) * std::sin(phi), std::cos(theta));
}

std::vector<Eigen::Vector3d> SamplePoints(const ReferenceView& ref) {
  const int w = ref.width ? ref.width : ref.camera.width();
  const int h = ref.height ? ref.height : ref.camera.height();
  std::vector<Eigen::Vector2d> q;
  q.reserve(static_cast<std::size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) q.emplace_back(ref.x0 + x, ref.y0 + y);
  const std::vector<Eigen::Vector3d> rays = ref.camera.Unproject(q);
  const Pose sample_from_cam = ref.cam_from_sample.Inverse();
  const Eigen::Matrix3d R = sample_from_cam.R();
  const Eigen::Vector3d origin = sample_from_cam.t;  // camera centre in the sample frame
  std::vector<Eigen::Vector3d> out(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d d = R * rays[i];
    const double lambda = -origin.z() / d.z();
    out[i] = lambda > 0 ? Eigen::Vector3d(origin + lambda * d)
                        : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  return out;
}

FloatPlanes ComputeCorrespondence(const ReferenceView& ref, const CalibratedView& view) {
  return ComputeCorrespondence(ref, SamplePoints(ref), view);
}

FloatPlanes ComputeCorrespondence(const ReferenceView& ref, const std::vector<Eigen::Vector3d>& p,
                                  const CalibratedView& view) {
  FloatPlanes out;
  out.width = ref.width ? ref.width : ref.camera.width();
  out.height = ref.height ? ref.height : ref.camera.height();
  const std::size_t n = p.size();
  for (const char* name : {"x", "y", "visible", "sample.x", "sample.y", "wi.x", "wi.y", "wi.z",
                           "wo.x", "wo.y", "wo.z"})
    out.planes[name].assign(n, kNaN);
  std::vector<Eigen::Vector3d> p_in_cam(n);
  for (std::size_t i = 0; i < n; ++i) p_in_cam[i] = view.cam_from_sample * p[i];
  const std::vector<Eigen::Vector2d> q = view.camera.Project(p_in_cam);
  const Eigen::Vector3d camera_in_sample =
      view.eye_in_sample_mm ? *view.eye_in_sample_mm : view.cam_from_sample.Inverse().t;
  const int W = view.camera.width(), H = view.camera.height();
  // The planes, looked up once rather than per pixel and channel.
  auto plane = [&out](const char* name) { return out.planes[name].data(); };
  float *x = plane("x"), *y = plane("y"), *visible = plane("visible");
  float *sample_x = plane("sample.x"), *sample_y = plane("sample.y");
  float* wi_planes[3] = {plane("wi.x"), plane("wi.y"), plane("wi.z")};
  float* wo_planes[3] = {plane("wo.x"), plane("wo.y"), plane("wo.z")};
  for (std::size_t i = 0; i < n; ++i) {
    if (!p[i].allFinite()) {
      visible[i] = 0;
      continue;
    }
    const Eigen::Vector3d wo = (camera_in_sample - p[i]).normalized();
    const Eigen::Vector3d wi = (view.light_in_sample_mm - p[i]).normalized();
    // Visible: in front of the camera, within the outermost pixel centres (so bilinear sampling
    // has all four neighbours), and the camera above the sample plane (it sees the face).
    const bool seen = p_in_cam[i].z() > 0 && q[i].allFinite() && q[i].x() >= 0 && q[i].y() >= 0 &&
                      q[i].x() <= W - 1 && q[i].y() <= H - 1 && wo.z() > 0;
    visible[i] = seen ? 1.f : 0.f;
    sample_x[i] = static_cast<float>(p[i].x());
    sample_y[i] = static_cast<float>(p[i].y());
    if (seen) {
      x[i] = static_cast<float>(q[i].x());
      y[i] = static_cast<float>(q[i].y());
    }
    for (int c = 0; c < 3; ++c) {
      wi_planes[c][i] = static_cast<float>(wi[c]);
      wo_planes[c][i] = static_cast<float>(wo[c]);
    }
  }
  out.attributes["acqFormat"] = "acq-correspondence-1";
  out.attributes["acqViewLensModel"] = view.camera.lensmodel_name();
  return out;
}

}  // namespace acq::calib
