// Reading the files a user describes a simulated sample with (a label image, mixture weights,
// a height map): what their readers share. PNGs among them are grey, one channel of 8 or 16
// bits; one reader for all, so that a colour image (a colour-coded label image, a normal map
// given as heights) is refused instead of silently read as its luminance.
#pragma once

#include <cstddef>
#include <opencv2/core.hpp>
#include <string>

namespace acq::sim {

// The image at `path` as one channel of CV_8U or CV_16U. A colour image whose channels are all
// equal (grey saved as RGB, with or without alpha) is accepted as that grey. `what` names the
// file's role in messages ("label image"), `fix` what the user should give instead; UserError
// when unreadable, in colour or of another depth.
cv::Mat ReadGreyImage(const std::string& path, const std::string& what, const std::string& fix);

// "pixel (x, y)" of a row-major index into an image `width` wide, for errors.
std::string PixelName(std::size_t index, int width);

}  // namespace acq::sim
