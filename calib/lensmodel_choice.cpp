#include "calib/lensmodel_choice.h"

#include <cmath>
#include <cstdio>

#include <Eigen/LU>
#include <Eigen/SVD>

#include "calib/uncertainty.h"
#include "core/error.h"

namespace acq::calib {

std::vector<std::string> DefaultLadder(int width, double focal_px) {
  return {"LENSMODEL_OPENCV4", "LENSMODEL_OPENCV5", "LENSMODEL_OPENCV8",
          SplinedModelFor(width, focal_px)};
}

double ProjectionDifference(const CameraModel& a, const CameraModel& b,
                            const std::vector<BoardObservation>& images, double distance_mm) {
  const int nx = 32, ny = 24;
  const std::vector<bool> covered = CoveredCells(a.width(), a.height(), images, nx, ny);
  std::vector<Eigen::Vector2d> q;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      if (covered[j * nx + i])
        q.emplace_back((i + 0.5) * a.width() / nx - 0.5, (j + 0.5) * a.height() / ny - 0.5);
  if (q.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::vector<Eigen::Vector3d> va = a.Unproject(q), vb = b.Unproject(q);
  // Kabsch with translation: the rigid transform T minimising sum |T pa - pb|^2 for the points
  // each model sees at `distance_mm` through the same pixels.
  Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < q.size(); ++i) {
    ca += va[i] * distance_mm / q.size();
    cb += vb[i] * distance_mm / q.size();
  }
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < q.size(); ++i)
    H += (va[i] * distance_mm - ca) * (vb[i] * distance_mm - cb).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  const Eigen::Vector3d t = cb - R * ca;
  std::vector<Eigen::Vector3d> rotated;
  for (const Eigen::Vector3d& v : va) rotated.push_back(R * v * distance_mm + t);
  const std::vector<Eigen::Vector2d> qb = b.Project(rotated);
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double d2 = (qb[i] - q[i]).squaredNorm();
    if (!std::isfinite(d2)) return std::numeric_limits<double>::infinity();  // model diverges
    sum += d2;
    ++n;
  }
  return std::sqrt(sum / n);
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
  LensModelChoice choice;
  for (const std::string& model : ladder) {
    IntrinsicsOptions o = options;
    o.lensmodel = model;
    const IntrinsicsSolution full = SolveIntrinsics(width, height, board, images, o);
    const IntrinsicsSolution a = SolveIntrinsics(width, height, board, half[0], o);
    const IntrinsicsSolution b = SolveIntrinsics(width, height, board, half[1], o);
    choice.rows.push_back({model, static_cast<int>(full.problem.camera().intrinsics().size()),
                           full.rms_per_coordinate,
                           ProjectionDifference(a.problem.camera(), b.problem.camera(), images,
                                                MedianBoardDistance(full.problem)),
                           full.solve_seconds});
  }
  // The noise floor: the smallest cross-validation difference on the ladder. A model that fits
  // the lens has a difference made of noise only; the richest model is meant to be that model,
  // but a spline the boards do not fully constrain shows its own indeterminacy instead
  // (docs/lens-model-choice.md), so the floor is taken over all rungs.
  double noise = std::numeric_limits<double>::infinity();
  for (const LadderRow& r : choice.rows) noise = std::min(noise, r.cv_diff_px);
  choice.noise_floor_px = noise;
  for (std::size_t i = 0; i < choice.rows.size(); ++i)
    if (choice.rows[i].cv_diff_px <= choice.noise_ratio * noise) {
      choice.chosen = static_cast<int>(i);
      break;
    }
  return choice;
}

void PrintLadder(std::FILE* out, const LensModelChoice& c) {
  std::fprintf(out, "%-62s %6s %10s %12s %9s\n", "model", "params", "RMS px", "CV diff px",
               "solve s");
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const LadderRow& r = c.rows[i];
    std::fprintf(out, "%-62s %6d %10.4f %12.4f %9.2f%s\n", r.lensmodel.c_str(), r.params,
                 r.rms_per_coordinate, r.cv_diff_px, r.solve_seconds,
                 static_cast<int>(i) == c.chosen ? "  <- chosen" : "");
  }
  std::fprintf(out,
               "criterion: the simplest model whose cross-validation difference is at most %.1f x "
               "the noise floor (the smallest on the ladder, %.4f px)\n",
               c.noise_ratio, c.noise_floor_px);
}

}  // namespace acq::calib
