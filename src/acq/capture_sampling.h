// A model's prediction sampled the way a validation view's capture was (issue 19;
// docs/reconstruction.md, "A prediction sampled as the capture was").
//
// The capture at a reference pixel is not the sample at that pixel's point: it is interpolated
// (correspondence_source.cpp, Sample) from the four view pixels around where the point lands in
// the view, and each of those saw its own point of the sample, up to a pixel or two away in the
// reference (an oblique view's pixels are foreshortened). On a smooth sample the two agree; where
// a highlight is a pixel wide (an embossed letter's edge on brass) the capture puts it where its
// view pixels happened to fall, a pixel or part of one from the reference pixel that holds it. A
// prediction at the reference pixels' own points is then compared with a capture that sampled
// other points: a map that puts the highlight at the right pixel is charged twice for it.
//
// Sampled as the capture was, the prediction is read at each of those four view pixels' points
// (the correspondence map inverted locally by its Jacobian), by the same bilinear rule the
// capture used, and weighted as the capture weighted them. Both sides then hold the sample
// sampled at the same points; a smooth prediction is unchanged to second order.
#pragma once

#include <cstdint>
#include <vector>

namespace acq {

// Where, per reference pixel, a view's capture was read in the view's image: the correspondence
// map's x and y (view pixels, mrcal's convention: a pixel's centre at integer coordinates); NaN
// where nothing was read. Empty: not known (data kept before the forty-first session).
struct CapturePositions {
  std::vector<float> x, y;
  bool empty() const { return x.empty(); }
};

// `predicted`: 3 values a pixel, row-major, made where known[p] is non-zero. Returns it sampled
// as the capture was; a pixel keeps its own value where its position is unknown, its
// neighbours' positions give no Jacobian, or a view pixel's point falls where no known
// prediction is near. Throws std::invalid_argument when the sizes disagree.
std::vector<float> SampleAsCaptured(int width, int height, const CapturePositions& positions,
                                    const std::vector<float>& predicted,
                                    const std::vector<std::uint8_t>& known);

}  // namespace acq
