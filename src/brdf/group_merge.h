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
#pragma once

#include <Eigen/Core>
#include <vector>

namespace acq {

inline constexpr double kMergeSeparation = 3.0;

// How far apart groups a and b lie (1 = the narrower group's RMS scatter): the features (n x F)
// of the pixels labelled a or b fitted jointly by an offset per group plus a quadratic in the
// field coordinates (n x 2, any smooth one-to-one function of position) shared by both; the
// offsets' distance over the residual scatter. With too few pixels for the shared terms (under
// 28), the plain distance of the means over the scatters. Infinite when a group has no scatter.
double GroupSeparation(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field,
                       const std::vector<int>& label, int a, int b);

// Merges the closest pair of groups under kMergeSeparation until none is left; labels stay
// dense in [0, groups). Returns the number of groups.
int MergeOverlapping(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field, int groups,
                     std::vector<int>* label);

}  // namespace acq
