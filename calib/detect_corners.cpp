#include "calib/detect_corners.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <mrgingham/mrgingham.hh>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace acq::calib {

Detector ParseDetector(const std::string& name, const BoardSpec& board) {
  Detector d;
  if (name == "auto" || name.empty())
    d = Detector::kAuto;
  else if (name == "mrgingham")
    d = Detector::kMrgingham;
  else if (name == "opencv")
    d = Detector::kOpencv;
  else
    throw UserError("--detector", "unknown detector '" + name + "'",
                    "use auto, mrgingham or opencv");
  if (d == Detector::kMrgingham && board.width_n != board.height_n)
    throw UserError("--detector mrgingham",
                    "mrgingham finds square N x N boards only, this board is " +
                        std::to_string(board.width_n) + "x" + std::to_string(board.height_n),
                    "use --detector opencv (or auto)");
  return d;
}

namespace {

cv::Mat To8Bit(const cv::Mat& image) {
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  if (grey.depth() == CV_8U) return grey;
  // Stretch the used range: a 12-bit image in a 16-bit container would otherwise be dark.
  double lo, hi;
  cv::minMaxLoc(grey, &lo, &hi);
  cv::Mat out;
  grey.convertTo(out, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0,
                 hi > lo ? -lo * 255.0 / (hi - lo) : 0);
  return out;
}

BoardObservation Mrgingham(const cv::Mat& grey, const BoardSpec& board) {
  std::vector<mrgingham::PointDouble> points;
  signed char* levels = nullptr;
  const int found =
      mrgingham::find_chessboard_from_image_array(points, &levels, board.width_n, grey);
  BoardObservation obs;
  if (found >= 0 && static_cast<int>(points.size()) == board.Corners()) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      const int level = levels ? levels[i] : 0;
      // A negative level is a corner mrgingham could not refine: mrcal treats it as missing.
      obs.corners.emplace_back(points[i].x, points[i].y,
                               level < 0 ? -1.0 : std::ldexp(1.0, -level));
    }
  }
  std::free(levels);
  return obs;
}

// `thorough`: adaptive thresholds and, when the classic detector fails, the exhaustive
// sector-based search (together 20 s and more on a 1280 x 1024 image that holds no such board:
// measured); otherwise one global threshold and the quick rejection of images without a board
// (about 10 ms).
BoardObservation Opencv(const cv::Mat& grey, const BoardSpec& board, bool thorough = true) {
  std::vector<cv::Point2f> points;
  const cv::Size pattern(board.width_n, board.height_n);
  BoardObservation obs;
  const int flags = cv::CALIB_CB_NORMALIZE_IMAGE |
                    (thorough ? cv::CALIB_CB_ADAPTIVE_THRESH : cv::CALIB_CB_FAST_CHECK);
  if (cv::findChessboardCorners(grey, pattern, points, flags)) {
    // Refine in a window as large as the squares allow (a larger window averages more edge
    // pixels) but never reaching the neighbouring corners: 0.35 of the smallest spacing.
    double spacing = 1e9;
    for (int j = 0; j < board.height_n; ++j)
      for (int i = 0; i + 1 < board.width_n; ++i)
        spacing = std::min<double>(
            spacing, cv::norm(points[j * board.width_n + i + 1] - points[j * board.width_n + i]));
    const int half = std::clamp(static_cast<int>(0.35 * spacing), 2, 20);
    cv::cornerSubPix(grey, points, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  } else if (!thorough ||
             !cv::findChessboardCornersSB(grey, pattern, points,
                                          cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY)) {
    // The classic detector fails on some strongly distorted or blurred views; the
    // sector-based one (sub-pixel by construction) is the fallback.
    return obs;
  }
  for (const cv::Point2f& p : points) obs.corners.emplace_back(p.x, p.y, 1.0);
  return obs;
}

}  // namespace

BoardObservation DetectCorners(const cv::Mat& image, const BoardSpec& board, Detector detector) {
  const cv::Mat grey = To8Bit(image);
  if (detector == Detector::kOpencv || board.width_n != board.height_n) return Opencv(grey, board);
  BoardObservation found = Mrgingham(grey, board);
  // auto: mrgingham misses boards of few pixels per square (under ~20, a long lens over a
  // small sample) that OpenCV's classic detector finds; its quick form, so that images without
  // the board (a wrong --board) are not searched exhaustively.
  if (!found.found() && detector == Detector::kAuto) return Opencv(grey, board, false);
  return found;
}

std::vector<BoardObservation> DetectCornersInFiles(const std::vector<std::string>& images,
                                                   const BoardSpec& board, Detector detector,
                                                   bool quiet) {
  std::vector<BoardObservation> out;
  for (const std::string& path : images) {
    const cv::Mat image = cv::imread(path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
    if (image.empty())
      throw UserError(path, "cannot read this image", "give PNG, TIFF or JPEG files that exist");
    BoardObservation obs = DetectCorners(image, board, detector);
    obs.image = path;
    if (!quiet)
      std::fprintf(stderr, "  %s: %s\n", path.c_str(),
                   obs.found() ? (std::to_string(obs.DetectedCorners()) + " corners").c_str()
                               : "no board found");
    out.push_back(std::move(obs));
  }
  return out;
}

}  // namespace acq::calib
