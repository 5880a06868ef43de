// Observations a material group's centre leaves out (pooled_model.h; docs/reconstruction.md,
// "Colour fringes at ink edges").
//
// A Bayer camera samples red, green and blue at different photosites, so where neighbouring
// points of the sample differ by orders of magnitude (a black fabric beside white paint's
// highlight: 550 to 1 on the colour card's view 8) a demosaiced pixel takes a channel from across
// the edge: its colour is a fringe, and a few percent of a dark ink's observations at its edges
// came out at zero or below. The centre of a group is a weighted mean of its pixels' normal
// equations, weighted towards the pixels nearest the sample's centre, which on the colour card is
// where three inks meet; so the fringes moved the black fabric's centre (1.34-1.45x its
// homogeneous error through acqd, 1.07x with a mono camera).
//
// Such an observation is told by its colour, not its level: at one view, the group's pixels near
// it on the sample (the near field's drift between them is small) have nearly its colour, while
// the level can change steeply between them (a highlight moving over the field). A test on the
// level dropped white paint's highlight (offline, no noise, 10 degrees: 0.3238 -> 0.3562); this
// one leaves the offline study unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace acq {

// An observation is left out when either of its log colour ratios departs from its neighbours'
// median by more than this many robust standard deviations of the view's departures (1.4826 x
// their median absolute value): far outside what noise does. 5 and 8 measured alike on the three
// colour cards; the larger leaves out less.
inline constexpr double kColourOutlierScales = 8;
// The group's pixels nearest in the field that an observation is compared with.
inline constexpr int kColourNeighbours = 16;
// Added to each view's robust scale (log space): without noise the departures are roundings,
// and a mono camera's are all zero, where nothing is an outlier.
inline constexpr double kColourScaleFloor = 0.01;

// field: the group's pixels' places in the field (n x 2; group_merge.h, FieldNeighbours).
// colour: n x (2 x views), each pixel's log colour at each view (the mapped red less the mapped
// green, then the mapped blue less the mapped green), NaN where the pixel has no observation
// there. A field of no extent (every pixel at the same directions) compares each observation
// with the whole group's median at its view. Returns n x views (row-major): 1 where the
// observation is left out.
std::vector<std::uint8_t> ColourOutliers(const Eigen::MatrixX2d& field,
                                         const Eigen::MatrixXd& colour, int views);

}  // namespace acq
