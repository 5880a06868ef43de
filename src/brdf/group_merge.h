// Joining the k-means groups of the pooled model (pooled_model.h) that are one material cut in
// pieces (docs/reconstruction.md, "Choosing the groups").
//
// Across a wide field a material's pixels see different directions, and their first solves, the
// features k-means groups by, drift with position. k-means cuts the drift into pieces side by
// side in the field, which held-out views then keep (each piece fits its own part of the field
// and extrapolates worse). Two groups are one material when their features, with a smooth drift
// over the field shared by both taken out, lie closer than kMergeSeparation times the narrower
// group's scatter: a normal blob cut in two gives halves 2.7 half-scatters apart; the narrower,
// so that a tight small material next to a wide one keeps its own group. Two materials seen at
// the same positions keep their distance whatever the drift.
//
// A quadratic does not always describe a material's drift over the whole field: with rows read
// between bins the card's white paint, cut in two side by side, lay 3.0-3.2 scatters apart on 6
// offline runs of 8. So two groups that meet in the field are also one material when their
// features do not jump where they meet: at the shared boundary a pixel's nearest neighbour of
// the other group is no farther from it in features than a neighbour of its own group as far
// from it in the field (the same noise and the same drift between each pair), up to
// kBoundaryStep. The pieces of white paint that this joins gave 1.13-1.37 on those runs; the
// pairs it keeps apart (groups of the 50-ink sample, the card at 10 degrees, mixes of a marbled
// sample) 1.43 and more: a thin margin (docs/reconstruction.md, "Choosing the groups").
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace acq {

inline constexpr double kMergeSeparation = 3.0;
// sqrt(2): a step across the boundary as large as the features' difference between two
// neighbours of one group.
inline constexpr double kBoundaryStep = 1.41421356237;
// Boundary pixels needed to judge a step: with 1-4 of them, two inks gave 0.86-1.03.
inline constexpr int kMinBoundaryPixels = 30;

// How far apart groups a and b lie (1 = the narrower group's RMS scatter): the features (n x F)
// of the pixels labelled a or b fitted jointly by an offset per group plus a quadratic in the
// field coordinates (n x 2, any smooth one-to-one function of position) shared by both; the
// offsets' distance over the residual scatter. With too few pixels for the shared terms (under
// 28), the plain distance of the means over the scatters. Infinite when a group has no scatter.
double GroupSeparation(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field,
                       const std::vector<int>& label, int a, int b);

// Each pixel's nearest `count` pixels in the field (n x 2), about: its neighbours on the sample,
// found in a grid of cells, among those of its own cell and the eight around it. None where the
// field has no extent.
inline constexpr int kBoundaryNeighbours = 6;
std::vector<std::vector<int>> FieldNeighbours(const Eigen::MatrixX2d& field,
                                              int count = kBoundaryNeighbours);

// Where groups a and b meet: over their pixels that have neighbours (`near`, FieldNeighbours) of
// both groups, the median feature distance to the other group's nearest over the median to the
// neighbour of their own group nearest that distance in the field. NaN with no such pixel.
struct BoundaryStep {
  int pixels = 0;
  double ratio = std::numeric_limits<double>::quiet_NaN();
};
BoundaryStep StepAtBoundary(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field,
                            const std::vector<std::vector<int>>& near,
                            const std::vector<int>& label, int a, int b);

// Merges the closest pair of groups under kMergeSeparation until none is left, and then, one
// pair at a time, the pair with the smallest step at its boundary under kBoundaryStep (from at
// least kMinBoundaryPixels pixels); labels stay dense in [0, groups). Returns the number of
// groups.
int MergeOverlapping(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field, int groups,
                     std::vector<int>* label);

// Whether two labellings of the same pixels cut them into the same groups, whatever the groups'
// numbers: the pooled model's search for the number of groups asks whether k-means, seeded with
// more groups, found anything new after the merge.
bool SameGrouping(const std::vector<int>& a, const std::vector<int>& b);

}  // namespace acq
