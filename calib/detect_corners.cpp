#include "calib/detect_corners.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <functional>

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

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// CornerLikeness above this is a corner: an ideal inner corner scores 1 (the first harmonic
// vanishes), the seam where the outermost squares meet the margin 2 sin(pi/2) / (2 sin(pi/2) +
// 2 sqrt 2 sin(pi/4)) = 0.41 (measured 0.38-0.44 on rendered boards, blur 0.6 px), a flat region
// or a straight edge less.
constexpr double kCornerScore = 0.7;

// How much the grey levels on a circle of radius `r` around `p` look like a chessboard's inner
// corner: the second angular harmonic (dark, light, dark, light) against the first (one side
// dark, as at the board's outer edge, where the last squares meet the margin). Returns the
// second harmonic's amplitude (grey levels) in `amplitude` and a score in [0, 1]: near 1 at an
// inner corner, below about 0.45 on an edge or in a flat region (docs/calibration.md).
double CornerLikeness(const cv::Mat& grey, const cv::Point2d& p, double r, double* amplitude) {
  const int n = 32;
  std::complex<double> h1 = 0, h2 = 0;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * M_PI * k / n;
    const cv::Point2d q(p.x + r * std::cos(t), p.y + r * std::sin(t));
    const int x = static_cast<int>(std::floor(q.x)), y = static_cast<int>(std::floor(q.y));
    const double fx = q.x - x, fy = q.y - y;
    auto at = [&](int xx, int yy) { return static_cast<double>(grey.at<std::uint8_t>(yy, xx)); };
    const double v = (1 - fy) * ((1 - fx) * at(x, y) + fx * at(x + 1, y)) +
                     fy * ((1 - fx) * at(x, y + 1) + fx * at(x + 1, y + 1));
    h1 += v * std::polar(1.0, t);
    h2 += v * std::polar(1.0, 2 * t);
  }
  const double a1 = 2 * std::abs(h1) / n, a2 = 2 * std::abs(h2) / n;
  *amplitude = a2;
  return a1 + a2 > 0 ? a2 / (a1 + a2) : 0;
}

}  // namespace

std::optional<BoardSide> BoardExtendsBeyond(const cv::Mat& image, const BoardSpec& board,
                                            const BoardObservation& found) {
  if (!found.found()) return std::nullopt;
  const cv::Mat grey = To8Bit(image);
  const int w = board.width_n, h = board.height_n;
  auto corner = [&](int i, int j) -> std::optional<cv::Point2d> {
    const Eigen::Vector3d& c = found.corners[j * w + i];
    if (c.z() <= 0) return std::nullopt;
    return cv::Point2d(c.x(), c.y());
  };
  auto inside = [&](const cv::Point2d& p, double r) {
    return p.x - r >= 0 && p.y - r >= 0 && p.x + r + 1 < grey.cols && p.y + r + 1 < grey.rows;
  };
  // The contrast of the detected corners themselves, the yardstick for a corner beyond.
  std::vector<double> inner;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i + 1 < w; ++i) {
      const auto a = corner(i, j), b = corner(i + 1, j);
      const double r = a && b ? 0.3 * cv::norm(*b - *a) : 0;
      if (!a || !b || !inside(*a, r)) continue;
      double amplitude;
      CornerLikeness(grey, *a, r, &amplitude);
      inner.push_back(amplitude);
    }
  if (inner.empty()) return std::nullopt;
  const double inner_amplitude = Median(inner);
  // Each side: corner k on the edge and its neighbour one step inside, (i, j) of both.
  using Ij = std::pair<int, int>;
  struct Side {
    BoardSide side;
    int count;
    std::function<Ij(int)> edge, next;
  };
  const Side sides[] = {
      {BoardSide::kLeft, h,
       [](int k) {
         return Ij{0, k};
       },
       [](int k) {
         return Ij{1, k};
       }},
      {BoardSide::kRight, h,
       [w](int k) {
         return Ij{w - 1, k};
       },
       [w](int k) {
         return Ij{w - 2, k};
       }},
      {BoardSide::kTop, w,
       [](int k) {
         return Ij{k, 0};
       },
       [](int k) {
         return Ij{k, 1};
       }},
      {BoardSide::kBottom, w,
       [h](int k) {
         return Ij{k, h - 1};
       },
       [h](int k) {
         return Ij{k, h - 2};
       }},
  };
  for (const Side& side : sides) {
    std::vector<double> scores, amplitudes;
    for (int k = 0; k < side.count; ++k) {
      const auto e = corner(side.edge(k).first, side.edge(k).second);
      const auto n = corner(side.next(k).first, side.next(k).second);
      if (!e || !n) continue;
      // One step further along the grid: a corner of the same board if it goes on, the seam of
      // the last squares and the margin if it ends there.
      const cv::Point2d beyond = 2 * *e - *n;
      const double r = 0.3 * cv::norm(*e - *n);
      if (!inside(beyond, r)) continue;
      double amplitude;
      scores.push_back(CornerLikeness(grey, beyond, r, &amplitude));
      amplitudes.push_back(amplitude);
    }
    // Half the side in view at least, so that a single stray corner-like spot cannot decide.
    if (2 * static_cast<int>(scores.size()) < side.count) continue;
    if (Median(scores) > kCornerScore && Median(amplitudes) > 0.5 * inner_amplitude)
      return side.side;
  }
  return std::nullopt;
}

std::string BoardSideName(BoardSide side) {
  switch (side) {
    case BoardSide::kLeft:
      return "left";
    case BoardSide::kRight:
      return "right";
    case BoardSide::kTop:
      return "top";
    case BoardSide::kBottom:
      return "bottom";
  }
  return "?";
}

namespace {

BoardObservation Detect(const cv::Mat& grey, const BoardSpec& board, Detector detector) {
  if (detector == Detector::kOpencv || board.width_n != board.height_n) return Opencv(grey, board);
  BoardObservation found = Mrgingham(grey, board);
  // auto: mrgingham misses boards of few pixels per square (under ~20, a long lens over a
  // small sample) that OpenCV's classic detector finds; its quick form, so that images without
  // the board (a wrong --board) are not searched exhaustively.
  if (!found.found() && detector == Detector::kAuto) return Opencv(grey, board, false);
  if (!found.found() && detector == Detector::kAutoInView) return Opencv(grey, board, true);
  return found;
}

}  // namespace

BoardObservation DetectCorners(const cv::Mat& image, const BoardSpec& board, Detector detector) {
  const cv::Mat grey = To8Bit(image);
  BoardObservation found = Detect(grey, board, detector);
  // A detector finds a W x H grid inside a larger board as readily as the whole board; the
  // solve would then take the corners for the wrong ones and fit a wrong lens without a sign.
  if (const std::optional<BoardSide> side = BoardExtendsBeyond(grey, board, found)) {
    const bool column = *side == BoardSide::kLeft || *side == BoardSide::kRight;
    const std::string larger =
        std::to_string(board.width_n + column) + "x" + std::to_string(board.height_n + !column);
    throw UserError(
        "--board " + std::to_string(board.width_n) + "x" + std::to_string(board.height_n),
        "the board in the image is larger: a further " + std::string(column ? "column" : "row") +
            " of inner corners lies beyond the " + BoardSideName(*side) + " of the grid found",
        "count the inner corners (where four squares meet) of the printed board; it "
        "has at least " +
            larger);
  }
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
    BoardObservation obs;
    try {
      obs = DetectCorners(image, board, detector);
    } catch (const UserError& e) {
      throw UserError(path + ": " + e.where(), e.problem(), e.fix());
    }
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
