// What a user needs to judge a calibration: residuals (stating the convention), outliers and the
// worst images, projection uncertainty at the centre and corners, and the diagnoses of a poor
// data set (too few boards, boards all facing the camera, boards only near the centre, boards
// missing or partly detected). `refuse` is set when the uncertainty exceeds the limit: the
// caller then writes no model unless forced.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "calib/corners.h"
#include "calib/intrinsics_solve.h"

namespace acq::calib {

struct ReportLimits {
  double max_uncertainty_px = 1.0;  // worst-direction stdev at centre and corners: refuse above
  int warn_boards = 10;             // fewer found boards: warn
  double warn_max_tilt_deg = 15;    // no board tilted more than this: warn (focal vs distance)
  double warn_coverage = 0.4;       // fraction of the imager (16 x 12 cells) with corners
};

struct CalibrationReport {
  struct Image {
    std::string name;
    bool found = false;
    int detected = 0, outliers = 0;
    double rms_px = 0;  // per coordinate, inliers
  };
  std::vector<Image> images;
  std::vector<int> worst;  // indices into images, by rms, worst first (up to 5)
  double distance_mm = 0;  // where the uncertainty is evaluated (median board distance)
  double uncertainty_centre_px = 0;
  double uncertainty_corner_px[4] = {0, 0, 0, 0};  // top-left, top-right, bottom-left, bottom-right
  double max_tilt_deg = 0;
  double coverage = 0;
  std::vector<std::string> warnings;
  bool refuse = false;
};

CalibrationReport MakeReport(const IntrinsicsSolution& solution,
                             const std::vector<BoardObservation>& images,
                             const ReportLimits& limits);
void PrintReport(std::FILE* out, const IntrinsicsSolution& solution,
                 const CalibrationReport& report);

// Fraction of a 16 x 12 grid of imager cells that hold at least one detected corner.
double ImagerCoverage(int width, int height, const std::vector<BoardObservation>& images);

}  // namespace acq::calib
