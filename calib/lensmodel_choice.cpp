#include "calib/lensmodel_choice.h"

#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "calib/uncertainty.h"
#include "core/error.h"

namespace acq::calib {

std::vector<std::string> DefaultLadder(int width, double focal_px) {
  return {"LENSMODEL_OPENCV4", "LENSMODEL_OPENCV5", "LENSMODEL_OPENCV8",
          SplinedModelFor(width, focal_px)};
}

std::vector<Eigen::Vector2d> SharedObservedPixels(int width, int height,
                                                  const std::vector<BoardObservation>& a,
                                                  const std::vector<BoardObservation>& b) {
  const int nx = 32, ny = 24;
  const std::vector<bool> in_a = CoveredCells(width, height, a, nx, ny);
  const std::vector<bool> in_b = CoveredCells(width, height, b, nx, ny);
  std::vector<Eigen::Vector2d> q;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (in_a[j * nx + i] && in_b[j * nx + i])
        q.emplace_back((i + 0.5) * width / nx - 0.5, (j + 0.5) * height / ny - 0.5);
  return q;
}

namespace {

// The rigid transform T minimising sum |T pa - pb|^2 (Kabsch with translation).
Eigen::Isometry3d BestRigidFit(const std::vector<Eigen::Vector3d>& pa,
                               const std::vector<Eigen::Vector3d>& pb) {
  Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < pa.size(); ++i) {
    ca += pa[i] / pa.size();
    cb += pb[i] / pa.size();
  }
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < pa.size(); ++i) H += (pa[i] - ca) * (pb[i] - cb).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = svd.matrixV() * D * svd.matrixU().transpose();
  T.translation() = cb - T.linear() * ca;
  return T;
}

}  // namespace

ProjectionDiff ProjectionDifference(const CameraModel& a, const CameraModel& b,
                                    const std::vector<Eigen::Vector2d>& pixels,
                                    double distance_mm) {
  ProjectionDiff out;
  out.points = static_cast<int>(pixels.size());
  const std::vector<Eigen::Vector3d> va = a.Unproject(pixels), vb = b.Unproject(pixels);
  // Only points both models unproject enter the fit; the others are divergences.
  std::vector<Eigen::Vector2d> q;
  std::vector<Eigen::Vector3d> pa, pb;
  for (std::size_t i = 0; i < pixels.size(); ++i)
    if (va[i].allFinite() && vb[i].allFinite()) {
      q.push_back(pixels[i]);
      pa.push_back(va[i] * distance_mm);
      pb.push_back(vb[i] * distance_mm);
    }
  out.diverged = out.points - static_cast<int>(q.size());
  if (q.empty()) {
    out.rms_px = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const Eigen::Isometry3d T = BestRigidFit(pa, pb);
  for (Eigen::Vector3d& p : pa) p = T * p;
  const std::vector<Eigen::Vector2d> qb = b.Project(pa);
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double d2 = (qb[i] - q[i]).squaredNorm();
    if (!std::isfinite(d2)) {
      ++out.diverged;
      continue;
    }
    sum += d2;
    ++n;
  }
  out.rms_px = n ? std::sqrt(sum / n) : std::numeric_limits<double>::quiet_NaN();
  return out;
}

LensModelChoice ChooseLensModel(int width, int height, const BoardSpec& board,
                                const std::vector<BoardObservation>& images,
                                const IntrinsicsOptions& options,
                                const std::vector<std::string>& ladder) {
  std::vector<BoardObservation> half[2];
  int k = 0;
  for (const BoardObservation& obs : images)
    if (obs.found()) half[k++ % 2].push_back(obs);
  if (k < 2 * options.min_boards)
    throw UserError("--lensmodel auto",
                    "cross-validation needs " + std::to_string(2 * options.min_boards) +
                        " boards (two halves), only " + std::to_string(k) + " were found",
                    "take more images, or name a lens model with --lensmodel");
  const std::vector<Eigen::Vector2d> shared = SharedObservedPixels(width, height, half[0], half[1]);
  if (shared.empty())
    throw UserError("--lensmodel auto",
                    "the two halves of the images observe no common part of the imager, so "
                    "their solves cannot be compared",
                    "take images with the board over the whole view, or name a lens model with "
                    "--lensmodel");
  LensModelChoice choice;
  for (const std::string& model : ladder) {
    IntrinsicsOptions o = options;
    o.lensmodel = model;
    const IntrinsicsSolution full = SolveIntrinsics(width, height, board, images, o);
    const IntrinsicsSolution a = SolveIntrinsics(width, height, board, half[0], o);
    const IntrinsicsSolution b = SolveIntrinsics(width, height, board, half[1], o);
    const ProjectionDiff diff = ProjectionDifference(a.problem.camera(), b.problem.camera(), shared,
                                                     MedianBoardDistance(full.problem));
    choice.rows.push_back({model, static_cast<int>(full.problem.camera().intrinsics().size()),
                           full.rms_per_coordinate, diff.rms_px, diff.points, diff.diverged,
                           full.solve_seconds});
  }
  // The noise floor: the smallest cross-validation difference on the ladder. A model that fits
  // the lens has a difference made of noise only; the richest model is meant to be that model,
  // but a spline the boards do not fully constrain shows its own indeterminacy instead
  // (docs/lens-model-choice.md), so the floor is taken over all rungs.
  // A model that does not project everywhere its own data lie is not a candidate.
  double noise = std::numeric_limits<double>::infinity();
  for (const LadderRow& r : choice.rows)
    if (r.cv_diverged == 0) noise = std::min(noise, r.cv_diff_px);
  choice.noise_floor_px = noise;
  for (std::size_t i = 0; i < choice.rows.size(); ++i)
    if (choice.rows[i].cv_diverged == 0 &&
        choice.rows[i].cv_diff_px <= choice.noise_ratio * noise) {
      choice.chosen = static_cast<int>(i);
      break;
    }
  if (choice.chosen < 0)
    throw UserError("--lensmodel auto",
                    "no model of the ladder projects everywhere its half of the images saw "
                    "the board",
                    "take more images, the board reaching every part of the view in both "
                    "halves, or name a lens model with --lensmodel");
  return choice;
}

void PrintLadder(std::FILE* out, const LensModelChoice& c) {
  std::fprintf(out, "%-62s %6s %10s %12s %9s\n", "model", "params", "RMS px", "CV diff px",
               "solve s");
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const LadderRow& r = c.rows[i];
    char diverged[80] = "";
    if (r.cv_diverged)
      std::snprintf(diverged, sizeof diverged, "  diverges at %d of %d points", r.cv_diverged,
                    r.cv_points);
    std::fprintf(out, "%-62s %6d %10.4f %12.4f %9.2f%s%s\n", r.lensmodel.c_str(), r.params,
                 r.rms_per_coordinate, r.cv_diff_px, r.solve_seconds, diverged,
                 static_cast<int>(i) == c.chosen ? "  <- chosen" : "");
  }
  const int points = c.rows.empty() ? 0 : c.rows.front().cv_points;
  std::fprintf(out,
               "compared at %d grid points where both halves saw corners; criterion: the simplest "
               "model that projects at all of them and whose cross-validation difference is at "
               "most %.1f x the noise floor (the smallest such difference, %.4f px)\n",
               points, c.noise_ratio, c.noise_floor_px);
}

}  // namespace acq::calib
