// A frame's preview for the live view (status.h's FramePreview): every s-th 2 x 2 block
// averaged (s even, so that a Bayer frame's colour sites average to grey and a mono frame is
// smoothed alike) into at most `max_side` pixels a side. Counted on the sampled blocks, not on
// every pixel: it runs on the capture's thread between a grab and the next move, and costs
// about 40,000 blocks whatever the frame's size.
//
// With it the focus aid: the centre's kFocusSide x kFocusSide blocks, every one of them, and
// their sharpness, the mean squared difference between neighbouring blocks over the squared
// mean block (a normalised gradient energy: a defocused picture loses its high frequencies and
// the figure falls; scaling the exposure scales both and cancels). It compares frames of one
// scene (turn the focus ring towards the higher figure), not different scenes. 16,384 blocks.
#pragma once

#include "hw/camera.h"
#include "session/status.h"

namespace acq {

inline constexpr int kPreviewMaxSide = 192;  // a 37 kB grey image, 49 kB in base64
inline constexpr int kFocusSide = 128;       // blocks a side: the centre's 256 x 256 pixels

FramePreview PreviewOf(const Frame& frame, int max_side = kPreviewMaxSide);

}  // namespace acq
