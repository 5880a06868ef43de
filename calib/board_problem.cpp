#include "calib/board_problem.h"

#include <cmath>
#include <limits>
#include <random>
#include <regex>

#include "core/error.h"

namespace acq::calib {

mrcal_problem_selections_t Selections::ToMrcal() const {
  mrcal_problem_selections_t s{};
  s.do_optimize_intrinsics_core = core;
  s.do_optimize_intrinsics_distortions = distortions;
  s.do_optimize_extrinsics = false;  // one stationary camera: it is the reference
  s.do_optimize_frames = frames;
  s.do_optimize_calobject_warp = warp;
  s.do_apply_regularization = regularization;
  s.do_apply_outlier_rejection = outlier_rejection;
  return s;
}

namespace {
// Point ranges apply to discrete points only; we have none.
const mrcal_problem_constants_t kConstants = {.point_min_range = -1.0, .point_max_range = -1.0};
}  // namespace

BoardProblem::BoardProblem(CameraModel camera, const BoardSpec& board,
                           const std::vector<BoardObservation>& images,
                           std::vector<Pose> cam_from_board)
    : camera_(std::move(camera)), board_(board), frames_(std::move(cam_from_board)) {
  int f = 0;
  for (const BoardObservation& obs : images) {
    if (!obs.found()) continue;
    for (const Eigen::Vector3d& c : obs.corners) {
      pool_.push_back({.x = c.x(), .y = c.y(), .z = c.z() > 0 ? c.z() : -1.0});
      initially_missing_ += c.z() <= 0;
    }
    observations_.push_back({.icam = {.intrinsics = 0, .extrinsics = -1}, .iframe = f++});
  }
  if (f != static_cast<int>(frames_.size()))
    throw std::logic_error("BoardProblem: one pose per found board expected");
}

int BoardProblem::Outliers() const {
  int n = 0;
  for (const mrcal_point3_t& p : pool_) n += p.z < 0;
  return n - initially_missing_;
}

int BoardProblem::States(const Selections& s) const {
  return mrcal_num_states(1, 0, Frames(), 0, 0, Frames(), s.ToMrcal(), &camera_.lensmodel());
}

int BoardProblem::BoardMeasurements() const {
  return mrcal_num_measurements_boards(Frames(), board_.width_n, board_.height_n);
}

// Unpacked state in mrcal's order: [core][distortions] [frames r t ...] [warp].
std::vector<double> BoardProblem::CurrentState(const Selections& s) const {
  std::vector<double> b;
  const std::vector<double>& in = camera_.intrinsics();
  if (s.core) b.insert(b.end(), in.begin(), in.begin() + 4);
  if (s.distortions) b.insert(b.end(), in.begin() + 4, in.end());
  if (s.frames)
    for (const Pose& p : frames_) {
      double rt[6];
      p.ToRt(rt);
      b.insert(b.end(), rt, rt + 6);
    }
  if (s.warp) b.insert(b.end(), {warp_.x2, warp_.y2});
  if (static_cast<int>(b.size()) != States(s))
    throw std::logic_error("BoardProblem: state layout differs from mrcal's");
  return b;
}

void BoardProblem::ApplyState(const Selections& s, const std::vector<double>& b) {
  std::size_t k = 0;
  std::vector<double>& in = camera_.intrinsics();
  if (s.core)
    for (int i = 0; i < 4; ++i) in[i] = b[k++];
  if (s.distortions)
    for (std::size_t i = 4; i < in.size(); ++i) in[i] = b[k++];
  if (s.frames)
    for (Pose& p : frames_) {
      p = Pose::FromRt(&b[k]);
      k += 6;
    }
  if (s.warp) {
    warp_.x2 = b[k++];
    warp_.y2 = b[k++];
  }
}

Eigen::VectorXd BoardProblem::StateScale(const Selections& s) const {
  std::vector<double> ones(States(s), 1.0);
  mrcal_unpack_solver_state_vector(ones.data(), 1, 0, Frames(), 0, 0, s.ToMrcal(),
                                   &camera_.lensmodel());
  return Eigen::Map<Eigen::VectorXd>(ones.data(), ones.size());
}

void BoardProblem::Optimize(const Selections& s) {
  std::vector<mrcal_pose_t> frames(frames_.size());
  for (std::size_t f = 0; f < frames_.size(); ++f) frames[f] = frames_[f].ToMrcal();
  const int imagersize[2] = {camera_.width(), camera_.height()};
  mrcal_calobject_warp_t warp = warp_;
  const mrcal_stats_t stats = mrcal_optimize(
      nullptr, 0, nullptr, 0, camera_.intrinsics().data(), nullptr, frames.data(), nullptr,
      s.warp ? &warp : nullptr, 1, 0, Frames(), 0, 0, observations_.data(), nullptr, Frames(), 0,
      pool_.data(), &camera_.lensmodel(), imagersize, s.ToMrcal(), &kConstants, board_.spacing_mm,
      board_.width_n, board_.height_n, false, false);
  if (!std::isfinite(stats.rms_reproj_error__pixels))
    throw UserError(camera_.lensmodel_name(), "mrcal's solve failed (no finite residual)",
                    "check that the board size and spacing match the board in the images");
  for (std::size_t f = 0; f < frames_.size(); ++f) frames_[f] = Pose::FromMrcal(frames[f]);
  if (s.warp) warp_ = warp;
}

std::vector<double> BoardProblem::Measurements(const Selections& s) const {
  const int nstate = States(s);
  const int nmeas = mrcal_num_measurements(Frames(), 0, board_.width_n, board_.height_n, 1, 0,
                                           Frames(), 0, 0, s.ToMrcal(), &camera_.lensmodel());
  std::vector<double> b(nstate), x(nmeas);
  std::vector<mrcal_pose_t> frames(frames_.size());
  for (std::size_t f = 0; f < frames_.size(); ++f) frames[f] = frames_[f].ToMrcal();
  const int imagersize[2] = {camera_.width(), camera_.height()};
  if (!mrcal_optimizer_callback(b.data(), nstate * sizeof(double), x.data(), nmeas * sizeof(double),
                                nullptr, camera_.intrinsics().data(), nullptr, frames.data(),
                                nullptr, &warp_, 1, 0, Frames(), 0, 0, observations_.data(),
                                nullptr, Frames(), 0, pool_.data(), &camera_.lensmodel(),
                                imagersize, s.ToMrcal(), &kConstants, board_.spacing_mm,
                                board_.width_n, board_.height_n, false))
    throw std::logic_error("mrcal_optimizer_callback failed");
  return x;
}

Eigen::MatrixXd BoardProblem::PackedDerivative(
    const Selections& s, const std::function<Eigen::VectorXd(const BoardProblem&)>& f) const {
  // Central differences in packed units, where every variable has a scale near 1: a step of
  // 1e-5 keeps truncation (h^2) and rounding (1e-16 / h) errors both near 1e-10.
  const double h = 1e-5;
  const std::vector<double> b0 = CurrentState(s);
  const Eigen::VectorXd scale = StateScale(s);
  BoardProblem work = *this;
  Eigen::MatrixXd out;
  for (std::size_t i = 0; i < b0.size(); ++i) {
    std::vector<double> b = b0;
    b[i] = b0[i] + h * scale[i];
    work.ApplyState(s, b);
    const Eigen::VectorXd plus = f(work);
    b[i] = b0[i] - h * scale[i];
    work.ApplyState(s, b);
    const Eigen::VectorXd minus = f(work);
    if (i == 0) out.resize(plus.size(), b0.size());
    out.col(i) = (plus - minus) / (2 * h);
  }
  return out;
}

Eigen::MatrixXd BoardProblem::Jacobian(const Selections& s) const {
  return PackedDerivative(s, [&s](const BoardProblem& p) {
    const std::vector<double> x = p.Measurements(s);
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()));
  });
}

std::vector<double> BoardProblem::Residuals() const {
  // mrcal's board measurements are weight * (projected - observed), 0 for outliers.
  const std::vector<double> x = Measurements(Selections{});
  std::vector<double> out(pool_.size() * 2);
  for (std::size_t i = 0; i < pool_.size(); ++i)
    for (int c = 0; c < 2; ++c)
      out[2 * i + c] =
          pool_[i].z > 0 ? x[2 * i + c] / pool_[i].z : std::numeric_limits<double>::quiet_NaN();
  return out;
}

double BoardProblem::RmsPerCoordinate(int* inliers) const {
  double sum = 0;
  int n = 0;
  for (double r : Residuals())
    if (std::isfinite(r)) {
      sum += r * r;
      ++n;
    }
  if (inliers) *inliers = n / 2;
  return n ? std::sqrt(sum / n) : 0.0;
}

void BoardProblem::ChangeLensModel(const std::string& lensmodel) {
  const int n = LensModelParams(lensmodel, "lens model");
  std::vector<double> in(camera_.intrinsics().begin(), camera_.intrinsics().begin() + 4);
  // As mrcal-calibrate-cameras seeds: tiny random distortions, the rational ones 1000x smaller
  // so the denominator starts at ~1 and the model starts as its simpler self.
  std::mt19937_64 rng(0);
  std::uniform_real_distribution<double> tiny(-1e-6, 1e-6);
  for (int i = 4; i < n; ++i) in.push_back(tiny(rng));
  static const std::regex opencv("LENSMODEL_OPENCV([0-9]+)");
  std::smatch m;
  if (std::regex_match(lensmodel, m, opencv) && std::stoi(m[1]) >= 8)
    for (int i = 4 + 5; i < 4 + 8; ++i) in[i] *= 1e-3;
  camera_ = CameraModel(lensmodel, in, camera_.width(), camera_.height());
}

}  // namespace acq::calib
