#include "calib/camera_model.h"

#include <cmath>
#include <filesystem>
#include <limits>

#include <Eigen/Geometry>

#include "core/error.h"

namespace acq::calib {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

mrcal_lensmodel_t ParseLensModel(const std::string& lensmodel, const std::string& where) {
  mrcal_lensmodel_t m{};
  if (!mrcal_lensmodel_from_name(&m, lensmodel.c_str()) || !mrcal_lensmodel_type_is_valid(m.type))
    throw UserError(where, "unknown or unconfigured lens model '" + lensmodel + "'",
                    "use a model name as mrcal spells it, e.g. LENSMODEL_OPENCV8 or "
                    "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=12_fov_x_deg=60");
  return m;
}

int LensModelParams(const std::string& lensmodel, const std::string& where) {
  const mrcal_lensmodel_t m = ParseLensModel(lensmodel, where);
  return mrcal_lensmodel_num_params(&m);
}

// Rotations through Eigen's angle-axis, not mrcal's r-composition, which is singular for
// half turns (and the sample frame is a half turn from the board frame).
Eigen::Matrix3d Pose::R() const {
  const double angle = r.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
}

namespace {
Eigen::Vector3d RFromMatrix(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}
}  // namespace

Eigen::Vector3d Pose::operator*(const Eigen::Vector3d& p) const {
  return R() * p + t;
}

Pose Pose::Inverse() const {
  const Eigen::Matrix3d Rt = R().transpose();
  Pose out;
  out.r = RFromMatrix(Rt);
  out.t = -(Rt * t);
  return out;
}

Pose Pose::Compose(const Pose& b_from_c) const {
  const Eigen::Matrix3d Ra = R();
  Pose out;
  out.r = RFromMatrix(Ra * b_from_c.R());
  out.t = Ra * b_from_c.t + t;
  return out;
}

Pose Pose::FromRt(const double rt[6]) {
  Pose p;
  p.r = {rt[0], rt[1], rt[2]};
  p.t = {rt[3], rt[4], rt[5]};
  return p;
}

void Pose::ToRt(double rt[6]) const {
  for (int i = 0; i < 3; ++i) {
    rt[i] = r[i];
    rt[3 + i] = t[i];
  }
}

mrcal_pose_t Pose::ToMrcal() const {
  mrcal_pose_t p;
  p.r = {.x = r[0], .y = r[1], .z = r[2]};
  p.t = {.x = t[0], .y = t[1], .z = t[2]};
  return p;
}

Pose Pose::FromMrcal(const mrcal_pose_t& p) {
  Pose out;
  out.r = {p.r.x, p.r.y, p.r.z};
  out.t = {p.t.x, p.t.y, p.t.z};
  return out;
}

CameraModel::CameraModel(const std::string& lensmodel, std::vector<double> intrinsics, int width,
                         int height)
    : name_(lensmodel),
      lensmodel_(ParseLensModel(lensmodel, "lens model")),
      intrinsics_(std::move(intrinsics)),
      width_(width),
      height_(height) {
  const int n = mrcal_lensmodel_num_params(&lensmodel_);
  if (static_cast<int>(intrinsics_.size()) != n)
    throw UserError(lensmodel, "needs " + std::to_string(n) + " intrinsics, got " +
                                   std::to_string(intrinsics_.size()));
  if (width <= 0 || height <= 0) throw UserError(lensmodel, "the imager size must be positive");
}

CameraModel CameraModel::Read(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw UserError(path, "camera model not found",
                    "give a .cameramodel written by `acq calibrate intrinsics` or by mrcal");
  mrcal_cameramodel_t* m = mrcal_read_cameramodel_file(path.c_str());
  if (m == nullptr)
    throw UserError(path, "is not a camera model mrcal can read",
                    "it must be a .cameramodel file (mrcal's format); see mrcal-show-models");
  char name[512];
  if (!mrcal_lensmodel_name(name, sizeof name, &m->lensmodel)) {
    mrcal_free_cameramodel(&m);
    throw UserError(path, "has a lens model whose name does not fit our buffer");
  }
  const int n = mrcal_lensmodel_num_params(&m->lensmodel);
  CameraModel out(name, std::vector<double>(m->intrinsics, m->intrinsics + n),
                  static_cast<int>(m->imagersize[0]), static_cast<int>(m->imagersize[1]));
  out.cam_from_ref = Pose::FromRt(m->rt_cam_ref);
  mrcal_free_cameramodel(&m);
  return out;
}

void CameraModel::Write(const std::string& path) const {
  // mrcal_cameramodel_t ends in a flexible array: allocate it with room for the intrinsics.
  std::vector<unsigned char> storage(sizeof(mrcal_cameramodel_t) +
                                     intrinsics_.size() * sizeof(double));
  auto* m = reinterpret_cast<mrcal_cameramodel_t*>(storage.data());
  cam_from_ref.ToRt(m->rt_cam_ref);
  m->imagersize[0] = static_cast<unsigned>(width_);
  m->imagersize[1] = static_cast<unsigned>(height_);
  m->lensmodel = lensmodel_;
  for (std::size_t i = 0; i < intrinsics_.size(); ++i) m->intrinsics[i] = intrinsics_[i];
  const std::string partial = path + ".partial";
  if (!mrcal_write_cameramodel_file(partial.c_str(), m))
    throw UserError(path, "could not write the camera model",
                    "check that the folder exists and is writable");
  std::filesystem::rename(partial, path);
}

std::vector<Eigen::Vector2d> CameraModel::Project(const std::vector<Eigen::Vector3d>& p) const {
  std::vector<mrcal_point3_t> in(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) in[i] = {.x = p[i].x(), .y = p[i].y(), .z = p[i].z()};
  std::vector<mrcal_point2_t> q(p.size());
  mrcal_project(q.data(), nullptr, nullptr, in.data(), static_cast<int>(p.size()), &lensmodel_,
                intrinsics_.data());
  std::vector<Eigen::Vector2d> out(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    out[i] = p[i].z() > 0 ? Eigen::Vector2d(q[i].x, q[i].y) : Eigen::Vector2d(kNaN, kNaN);
  return out;
}

Eigen::Vector2d CameraModel::Project(const Eigen::Vector3d& p) const {
  return Project(std::vector<Eigen::Vector3d>{p})[0];
}

std::vector<Eigen::Vector3d> CameraModel::Unproject(const std::vector<Eigen::Vector2d>& q) const {
  std::vector<mrcal_point2_t> in(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) in[i] = {.x = q[i].x(), .y = q[i].y()};
  std::vector<mrcal_point3_t> v(q.size());
  if (!mrcal_unproject(v.data(), in.data(), static_cast<int>(q.size()), &lensmodel_,
                       intrinsics_.data()))
    throw UserError(name_, "mrcal could not unproject with this lens model");
  std::vector<Eigen::Vector3d> out(q.size());
  for (std::size_t i = 0; i < q.size(); ++i)
    out[i] = Eigen::Vector3d(v[i].x, v[i].y, v[i].z).normalized();
  return out;
}

Eigen::Vector3d CameraModel::Unproject(const Eigen::Vector2d& q) const {
  return Unproject(std::vector<Eigen::Vector2d>{q})[0];
}

}  // namespace acq::calib
