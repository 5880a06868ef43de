// A merged pose's thumbnail (issue 23): hdr/<pose>.png beside hdr/<pose>.exr, for the live
// view's strip of finished poses and for a person looking at a session folder without an EXR
// viewer. Box-averaged (up to 4 x 4 pixels read per block) to at most kThumbnailMaxSide pixels a
// side, in camera RGB (the colour matrix comes later, from the chart), scaled so that the 99th
// percentile of the unflagged pixels lands at 0.9, sRGB-encoded; a block holding a pixel saturated
// in every exposure is drawn magenta, so that clipping the bracket did not cure shows at a glance.
#pragma once

#include <string>

#include "acq/hdr.h"

namespace acq {

inline constexpr int kThumbnailMaxSide = 192;

// Written aside and renamed into place; throws UserError naming the file when it cannot be.
void WriteHdrThumbnail(const HdrImage& hdr, const std::string& path);

}  // namespace acq
