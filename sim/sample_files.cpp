#include "sim/sample_files.h"

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "core/error.h"

namespace acq::sim {

cv::Mat ReadGreyImage(const std::string& path, const std::string& what, const std::string& fix) {
  const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw UserError(path, "cannot read the " + what, fix);
  if (image.depth() != CV_8U && image.depth() != CV_16U)
    throw UserError(path, "the " + what + " is neither 8- nor 16-bit", fix);
  if (image.channels() == 1) return image;
  std::vector<cv::Mat> planes;
  cv::split(image, planes);
  // Channels 0-2 are colour; a fourth is alpha, which a grey image may carry and we ignore.
  const int colours = std::min(image.channels(), 3);
  for (int c = 1; c < colours; ++c)
    if (cv::countNonZero(planes[0] != planes[c]) > 0)
      throw UserError(path, "the " + what + " is in colour (its channels differ)",
                      fix + "; a colour image's luminance is not taken as values");
  return planes[0];
}

std::string PixelName(std::size_t index, int width) {
  return "pixel (" + std::to_string(index % std::size_t(width)) + ", " +
         std::to_string(index / std::size_t(width)) + ")";
}

}  // namespace acq::sim
