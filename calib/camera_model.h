// A camera: mrcal lens model, intrinsics and imager size, plus the pose rt_cam_ref (mrcal's
// rt convention: Rodrigues rotation then translation). Read and written as mrcal .cameramodel
// files through mrcal's own C reader and writer, so mrcal's Python tools open what we write and
// we open what they write.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/mrcal_c.h"

namespace acq::calib {

// A rigid transform in mrcal's rt form: x_a = R(r) x_b + t for a_from_b.
struct Pose {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const;
  Pose Inverse() const;
  Pose Compose(const Pose& b_from_c) const;  // this = a_from_b; returns a_from_c
  Eigen::Matrix3d R() const;
  static Pose FromRt(const double rt[6]);
  void ToRt(double rt[6]) const;
  mrcal_pose_t ToMrcal() const;
  static Pose FromMrcal(const mrcal_pose_t& p);
};

class CameraModel {
 public:
  CameraModel() = default;
  // Throws UserError naming `lensmodel` when mrcal does not know it or the count is wrong.
  CameraModel(const std::string& lensmodel, std::vector<double> intrinsics, int width, int height);

  static CameraModel Read(const std::string& path);  // UserError naming the file
  void Write(const std::string& path) const;         // to a temporary name, then renamed

  const std::string& lensmodel_name() const { return name_; }
  const mrcal_lensmodel_t& lensmodel() const { return lensmodel_; }
  const std::vector<double>& intrinsics() const { return intrinsics_; }
  std::vector<double>& intrinsics() { return intrinsics_; }
  int width() const { return width_; }
  int height() const { return height_; }
  Pose cam_from_ref;  // identity for a single calibrated camera

  // Points in the camera frame -> pixels. NaN for points at or behind the camera plane.
  Eigen::Vector2d Project(const Eigen::Vector3d& p_in_cam) const;
  std::vector<Eigen::Vector2d> Project(const std::vector<Eigen::Vector3d>& p_in_cam) const;
  // Pixels -> unit ray directions in the camera frame (mrcal's iterative unprojection).
  Eigen::Vector3d Unproject(const Eigen::Vector2d& q) const;
  std::vector<Eigen::Vector3d> Unproject(const std::vector<Eigen::Vector2d>& q) const;

 private:
  std::string name_;
  mrcal_lensmodel_t lensmodel_{};
  std::vector<double> intrinsics_;
  int width_ = 0, height_ = 0;
};

// Number of intrinsics a named model needs; UserError naming `where` for an unknown name.
int LensModelParams(const std::string& lensmodel, const std::string& where);
mrcal_lensmodel_t ParseLensModel(const std::string& lensmodel, const std::string& where);

}  // namespace acq::calib
