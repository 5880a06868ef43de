#include "calib/intrinsics_report.h"

#include <algorithm>
#include <cmath>

#include "calib/uncertainty.h"
#include "core/angles.h"

namespace acq::calib {

double ImagerCoverage(int width, int height, const std::vector<BoardObservation>& images) {
  const std::vector<bool> hit = CoveredCells(width, height, images, 16, 12);
  return static_cast<double>(std::count(hit.begin(), hit.end(), true)) / hit.size();
}

CalibrationReport MakeReport(const IntrinsicsSolution& solution,
                             const std::vector<BoardObservation>& images,
                             const ReportLimits& limits) {
  CalibrationReport r;
  const BoardProblem& p = solution.problem;
  const std::vector<double> residuals = p.Residuals();
  const int corners = p.board().Corners();
  for (const BoardObservation& obs : images)
    r.images.push_back({obs.image, obs.found(), obs.DetectedCorners(), 0, 0});
  for (int f = 0; f < p.Frames(); ++f) {
    CalibrationReport::Image& im = r.images[solution.image_of_frame[f]];
    double sum = 0;
    int n = 0;
    for (int i = 0; i < corners; ++i) {
      const double rx = residuals[2 * (f * corners + i)], ry = residuals[2 * (f * corners + i) + 1];
      if (std::isfinite(rx)) {
        sum += rx * rx + ry * ry;
        ++n;
      }
    }
    im.outliers = im.detected - n;
    im.rms_px = n ? std::sqrt(sum / (2.0 * n)) : 0;
  }
  std::vector<int> order;
  for (std::size_t i = 0; i < r.images.size(); ++i)
    if (r.images[i].found) order.push_back(static_cast<int>(i));
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return r.images[a].rms_px > r.images[b].rms_px; });
  order.resize(std::min<std::size_t>(order.size(), 5));
  r.worst = order;

  // Uncertainty at the working distance, at the centre and 5% in from each corner.
  const CameraModel& cam = p.camera();
  r.distance_mm = MedianBoardDistance(p);
  const UncertaintyModel uncertainty(p, solution.selections, solution.rms_per_coordinate);
  const double w = cam.width(), h = cam.height();
  r.uncertainty_centre_px = uncertainty.WorstStdev({(w - 1) / 2, (h - 1) / 2}, r.distance_mm);
  const Eigen::Vector2d corner_q[4] = {
      {0.05 * w, 0.05 * h}, {0.95 * w, 0.05 * h}, {0.05 * w, 0.95 * h}, {0.95 * w, 0.95 * h}};
  for (int i = 0; i < 4; ++i)
    r.uncertainty_corner_px[i] = uncertainty.WorstStdev(corner_q[i], r.distance_mm);

  for (const Pose& pose : p.cam_from_board()) {
    const Eigen::Vector3d normal = pose.R().col(2);
    r.max_tilt_deg =
        std::max(r.max_tilt_deg, RadToDeg(std::acos(std::min(1.0, std::abs(normal.z())))));
  }
  r.coverage = ImagerCoverage(cam.width(), cam.height(), images);

  char line[400];
  const int found = p.Frames();
  if (found < limits.warn_boards) {
    std::snprintf(line, sizeof line,
                  "only %d boards: the solve is weakly constrained (projection uncertainty at "
                  "the centre %.3f px); take %d or more",
                  found, r.uncertainty_centre_px, limits.warn_boards);
    r.warnings.push_back(line);
  }
  if (r.max_tilt_deg < limits.warn_max_tilt_deg) {
    std::snprintf(line, sizeof line,
                  "every board is nearly facing the camera (largest tilt %.1f deg): focal length "
                  "and distance are confounded (uncertainty at the centre %.3f px); tilt the "
                  "board 30-45 deg in several directions",
                  r.max_tilt_deg, r.uncertainty_centre_px);
    r.warnings.push_back(line);
  }
  const double worst_corner =
      *std::max_element(r.uncertainty_corner_px, r.uncertainty_corner_px + 4);
  if (r.coverage < limits.warn_coverage) {
    std::snprintf(line, sizeof line,
                  "the boards cover only %.0f%% of the imager: the lens model is extrapolated "
                  "towards the edges (uncertainty at the corners up to %.3f px); move the board "
                  "into the corners of the view",
                  100 * r.coverage, worst_corner);
    r.warnings.push_back(line);
  }
  int missing = 0, partial = 0;
  for (const CalibrationReport::Image& im : r.images) {
    missing += !im.found;
    partial += im.found && im.detected < p.board().Corners();
  }
  if (missing) {
    std::snprintf(line, sizeof line, "%d of %zu images have no board found (listed above)", missing,
                  r.images.size());
    r.warnings.push_back(line);
  }
  if (partial) {
    std::snprintf(line, sizeof line, "%d images have the board only partly detected", partial);
    r.warnings.push_back(line);
  }
  const double worst = std::max(worst_corner, r.uncertainty_centre_px);
  if (!(worst <= limits.max_uncertainty_px)) {
    std::snprintf(line, sizeof line,
                  "projection uncertainty %.3f px exceeds the limit %.3f px: this model would be "
                  "worse than a calibration should claim",
                  worst, limits.max_uncertainty_px);
    r.warnings.push_back(line);
    r.refuse = true;
  }
  return r;
}

void PrintReport(std::FILE* out, const IntrinsicsSolution& s, const CalibrationReport& r) {
  const BoardProblem& p = s.problem;
  std::fprintf(out, "lens model: %s (%zu parameters)\n", p.camera().lensmodel_name().c_str(),
               p.camera().intrinsics().size());
  std::fprintf(out, "intrinsics:");
  for (double v : p.camera().intrinsics()) std::fprintf(out, " %.6g", v);
  std::fprintf(out, "\nboard warp (mm): x2 %.4f, y2 %.4f\n", p.warp().x(), p.warp().y());
  std::fprintf(out,
               "residual RMS: %.4f px per coordinate (mrcal's convention) = %.4f px per point "
               "(OpenCV's, x sqrt 2), over %d inlier corners in %d boards\n",
               s.rms_per_coordinate, s.rms_per_point, s.inliers, p.Frames());
  std::fprintf(out, "outliers rejected: %d\n", p.Outliers());
  std::fprintf(out, "per image (corners detected, outliers, RMS px per coordinate):\n");
  for (const CalibrationReport::Image& im : r.images) {
    if (im.found)
      std::fprintf(out, "  %-40s %4d %3d %8.4f\n", im.name.c_str(), im.detected, im.outliers,
                   im.rms_px);
    else
      std::fprintf(out, "  %-40s no board found\n", im.name.c_str());
  }
  std::fprintf(out, "worst images:");
  for (int i : r.worst)
    std::fprintf(out, " %s (%.3f)", r.images[i].name.c_str(), r.images[i].rms_px);
  std::fprintf(out,
               "\nprojection uncertainty (worst-direction stdev, mrcal's mean-frames method) at "
               "%.0f mm:\n  centre %.4f px; corners %.4f %.4f %.4f %.4f px\n",
               r.distance_mm, r.uncertainty_centre_px, r.uncertainty_corner_px[0],
               r.uncertainty_corner_px[1], r.uncertainty_corner_px[2], r.uncertainty_corner_px[3]);
  std::fprintf(out, "largest board tilt %.1f deg; imager coverage %.0f%%; solve %.2f s\n",
               r.max_tilt_deg, 100 * r.coverage, s.solve_seconds);
  for (const std::string& w : r.warnings) std::fprintf(out, "WARNING: %s\n", w.c_str());
}

}  // namespace acq::calib
