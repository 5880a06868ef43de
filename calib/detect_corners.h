// Chessboard corner detection: mrgingham for square N x N boards (what mrcal's tools use),
// OpenCV's detector with sub-pixel refinement for any W x H board.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners.h"

namespace acq::calib {

enum class Detector { kAuto, kMrgingham, kOpencv };
// "auto" (mrgingham for square boards, OpenCV for others and where mrgingham finds no board),
// "mrgingham", "opencv".
Detector ParseDetector(const std::string& name, const BoardSpec& board);

// Corners of `board` in an 8- or 16-bit grey image; an empty observation when not found.
// The returned observation's `image` is left empty for the caller to name.
BoardObservation DetectCorners(const cv::Mat& image, const BoardSpec& board, Detector detector);

// Reads each image (UserError naming a file that cannot be read) and detects; prints one line
// per image to stderr unless quiet.
std::vector<BoardObservation> DetectCornersInFiles(const std::vector<std::string>& images,
                                                   const BoardSpec& board, Detector detector,
                                                   bool quiet);

}  // namespace acq::calib
