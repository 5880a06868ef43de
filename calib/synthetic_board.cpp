#include "calib/synthetic_board.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include "core/angles.h"

namespace acq::calib {

namespace {

bool InImager(const CameraModel& camera, const Eigen::Vector2d& q) {
  return std::isfinite(q.x()) && q.x() >= 0 && q.y() >= 0 && q.x() <= camera.width() - 1 &&
         q.y() <= camera.height() - 1;
}

// Rays on a coarse pixel grid, interpolated: mrcal's unprojection is iterative and a rendered
// image needs tens of millions of rays. The lens models are smooth; at a 4 px step the
// interpolated ray is within 1e-4 px of the exact one (checked in test_calibration).
class RayGrid {
 public:
  RayGrid(const CameraModel& camera, double step) : step_(step) {
    nx_ = static_cast<int>(std::ceil((camera.width() + 1) / step)) + 2;
    ny_ = static_cast<int>(std::ceil((camera.height() + 1) / step)) + 2;
    std::vector<Eigen::Vector2d> q;
    q.reserve(nx_ * ny_);
    for (int j = 0; j < ny_; ++j)
      for (int i = 0; i < nx_; ++i) q.emplace_back(-1 + i * step, -1 + j * step);
    const std::vector<Eigen::Vector3d> v = camera.Unproject(q);
    xy_.resize(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) xy_[i] = v[i].head<2>() / v[i].z();
  }
  // Ray (x/z, y/z, 1) through pixel position q.
  Eigen::Vector3d operator()(double qx, double qy) const {
    const double fx = (qx + 1) / step_, fy = (qy + 1) / step_;
    const int i = std::clamp(static_cast<int>(fx), 0, nx_ - 2);
    const int j = std::clamp(static_cast<int>(fy), 0, ny_ - 2);
    const double a = fx - i, b = fy - j;
    const Eigen::Vector2d xy =
        (1 - a) * (1 - b) * xy_[j * nx_ + i] + a * (1 - b) * xy_[j * nx_ + i + 1] +
        (1 - a) * b * xy_[(j + 1) * nx_ + i] + a * b * xy_[(j + 1) * nx_ + i + 1];
    return {xy.x(), xy.y(), 1.0};
  }

 private:
  double step_;
  int nx_, ny_;
  std::vector<Eigen::Vector2d> xy_;
};

// Reflectance of the board at (x, y) in the board frame: 0 black, 1 white, -1 off the board.
double BoardAlbedo(const BoardSpec& board, double x, double y) {
  const double s = board.spacing_mm;
  // Squares span [-s, W s] x [-s, H s]; a white margin one square wide surrounds them.
  if (x < -2 * s || y < -2 * s || x > (board.width_n + 1) * s || y > (board.height_n + 1) * s)
    return -1;
  if (x < -s || y < -s || x > board.width_n * s || y > board.height_n * s) return 1;
  const int ix = static_cast<int>(std::floor(x / s)) + 1;
  const int iy = static_cast<int>(std::floor(y / s)) + 1;
  return (ix + iy) % 2 == 0 ? 0 : 1;
}

}  // namespace

CameraModel ExampleCamera() {
  return CameraModel("LENSMODEL_OPENCV8",
                     {1000, 995, 645.3, 508.1, 0.3, -0.1, 2e-4, -3e-4, 0.05, 0.4, -0.05, 0.02},
                     1280, 1024);
}

Pose CamFromSampleLookingAtCentre(const Eigen::Vector3d& camera_in_sample) {
  const Eigen::Vector3d z = -camera_in_sample.normalized();
  // Horizontal x: perpendicular to the viewing direction within the sample plane; straight
  // down, the sample's x.
  Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(z);
  x = x.norm() < 1e-9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d(x.normalized());
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d cam_from_sample;
  cam_from_sample.row(0) = x;
  cam_from_sample.row(1) = y;
  cam_from_sample.row(2) = z;
  Pose p;
  const Eigen::AngleAxisd aa(cam_from_sample);
  p.r = aa.axis() * aa.angle();
  p.t = -(cam_from_sample * camera_in_sample);
  return p;
}

std::vector<Pose> SampleBoardPoses(const CameraModel& camera, const BoardSpec& board, int n,
                                   const BoardPoseSampling& sampling) {
  std::mt19937_64 rng(sampling.seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const double s = board.spacing_mm;
  // Corners of the board's outline (with margin) and its grid, checked against the imager.
  std::vector<Eigen::Vector3d> check = board.CornersInBoard();
  if (sampling.whole_board_in_view)
    for (double x : {-2 * s, (board.width_n + 1) * s})
      for (double y : {-2 * s, (board.height_n + 1) * s}) check.emplace_back(x, y, 0);
  std::vector<Pose> out;
  for (int attempt = 0; static_cast<int>(out.size()) < n && attempt < 1000 * n; ++attempt) {
    const double spread = sampling.centre_spread;
    const Eigen::Vector2d q_centre(camera.width() * (0.5 + spread * (unit(rng) - 0.5)),
                                   camera.height() * (0.5 + spread * (unit(rng) - 0.5)));
    const double distance = sampling.min_distance_mm +
                            unit(rng) * (sampling.max_distance_mm - sampling.min_distance_mm);
    const Eigen::Vector3d centre_in_cam = camera.Unproject(q_centre) * distance;
    // Tilt: the board normal within max_tilt of the optical axis, any spin about it.
    const double tilt = DegToRad(sampling.max_tilt_deg) * std::sqrt(unit(rng));
    const double tilt_azimuth = 2 * M_PI * unit(rng), spin = 2 * M_PI * unit(rng);
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(tilt_azimuth),
                                                                       std::sin(tilt_azimuth), 0)) *
                               Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    Pose pose;
    const Eigen::AngleAxisd aa(R);
    pose.r = aa.axis() * aa.angle();
    pose.t = centre_in_cam - R * board.Centre();
    std::vector<Eigen::Vector3d> p_in_cam;
    for (const Eigen::Vector3d& p : check) p_in_cam.push_back(R * p + pose.t);
    int inside = 0;
    for (const Eigen::Vector2d& q : camera.Project(p_in_cam)) inside += InImager(camera, q);
    // A partly visible board (as in real data, pushed into the corners of the view) needs at
    // least half its corners in view.
    if (sampling.whole_board_in_view ? inside == static_cast<int>(check.size())
                                     : 2 * inside >= board.Corners())
      out.push_back(pose);
  }
  return out;
}

std::vector<BoardObservation> SynthesizeCorners(const CameraModel& camera, const BoardSpec& board,
                                                const std::vector<Pose>& cam_from_board,
                                                double noise_px, std::uint64_t seed,
                                                const Eigen::Vector2d& warp_mm) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, noise_px);
  std::vector<BoardObservation> out;
  const std::vector<Eigen::Vector3d> corners = board.CornersInBoard(warp_mm);
  for (std::size_t f = 0; f < cam_from_board.size(); ++f) {
    std::vector<Eigen::Vector3d> p_in_cam;
    for (const Eigen::Vector3d& p : corners) p_in_cam.push_back(cam_from_board[f] * p);
    BoardObservation obs;
    obs.image = "synthetic-" + std::to_string(f) + ".png";
    for (const Eigen::Vector2d& q : camera.Project(p_in_cam)) {
      const Eigen::Vector2d noisy(q.x() + noise(rng), q.y() + noise(rng));
      obs.corners.emplace_back(noisy.x(), noisy.y(), InImager(camera, q) ? 1.0 : -1.0);
    }
    out.push_back(std::move(obs));
  }
  return out;
}

cv::Mat RenderBoard(const CameraModel& camera, const BoardSpec& board, const Pose& cam_from_board,
                    const BoardRenderOptions& options) {
  const RayGrid rays(camera, options.ray_grid_step_px);
  const Pose board_from_cam = cam_from_board.Inverse();
  const Eigen::Matrix3d R = board_from_cam.R();
  const Eigen::Vector3d origin = board_from_cam.t;  // camera centre in the board frame
  const int ss = std::max(1, options.supersample);
  cv::Mat radiance(camera.height(), camera.width(), CV_32F);
#pragma omp parallel for schedule(dynamic, 16)
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      double sum = 0;
      for (int sy = 0; sy < ss; ++sy)
        for (int sx = 0; sx < ss; ++sx) {
          // mrcal's pixel convention: pixel (x, y) covers [x - 0.5, x + 0.5].
          const Eigen::Vector3d d = R * rays(x - 0.5 + (sx + 0.5) / ss, y - 0.5 + (sy + 0.5) / ss);
          const double lambda = -origin.z() / d.z();
          double albedo = -1;
          if (lambda > 0) {
            const Eigen::Vector3d p = origin + lambda * d;
            albedo = BoardAlbedo(board, p.x(), p.y());
          }
          sum += albedo < 0 ? options.background
                            : options.black + albedo * (options.white - options.black);
        }
      radiance.at<float>(y, x) = static_cast<float>(sum / (ss * ss));
    }
  }
  if (options.blur_px > 0) cv::GaussianBlur(radiance, radiance, cv::Size(0, 0), options.blur_px);
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> noise(0, options.noise_dn);
  cv::Mat out(camera.height(), camera.width(), CV_8U);
  for (int y = 0; y < camera.height(); ++y)
    for (int x = 0; x < camera.width(); ++x)
      out.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(
          std::lround(radiance.at<float>(y, x) + (options.noise_dn > 0 ? noise(rng) : 0.0)));
  return out;
}

}  // namespace acq::calib
