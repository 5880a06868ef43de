// Chessboard corner detection: mrgingham for square N x N boards (what mrcal's tools use),
// OpenCV's detector with sub-pixel refinement for any W x H board.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "calib/board.h"
#include "calib/corners.h"

namespace acq::calib {

// kAuto: mrgingham for square boards, OpenCV for others and, in its quick form, where mrgingham
// finds no board (images without the board, a wrong --board, are not searched exhaustively).
// kAutoInView: the same, but OpenCV's full search where mrgingham finds none: for images known
// to show the board (a session's board captures), where a miss loses a view.
enum class Detector { kAuto, kAutoInView, kMrgingham, kOpencv };
// "auto" (kAuto), "mrgingham", "opencv".
Detector ParseDetector(const std::string& name, const BoardSpec& board);

// Corners of `board` in an 8- or 16-bit grey image; an empty observation when not found.
// The returned observation's `image` is left empty for the caller to name. UserError when the
// grid found is part of a larger board (BoardExtendsBeyond): --board does not match the print.
BoardObservation DetectCorners(const cv::Mat& image, const BoardSpec& board, Detector detector);

enum class BoardSide { kLeft, kRight, kTop, kBottom };

// Whether the board in `image` has a further row or column of inner corners beyond one side of
// the grid `found` (a board larger than `board` says: a detector finds a W x H grid inside a
// larger board as readily as the whole board). The side, or nothing.
std::optional<BoardSide> BoardExtendsBeyond(const cv::Mat& image, const BoardSpec& board,
                                            const BoardObservation& found);
std::string BoardSideName(BoardSide side);

// Reads each image (UserError naming a file that cannot be read) and detects; prints one line
// per image to stderr unless quiet.
std::vector<BoardObservation> DetectCornersInFiles(const std::vector<std::string>& images,
                                                   const BoardSpec& board, Detector detector,
                                                   bool quiet);

}  // namespace acq::calib
