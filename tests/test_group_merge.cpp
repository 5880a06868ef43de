// The merge of the pooled model's k-means groups (brdf/group_merge.h), on features made to
// drift across the field as a material's first solves do in the near field.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "brdf/group_merge.h"

using namespace acq;

namespace {

// Material A in two patches at opposite ends of the field (x near -1 and near +1), its
// features drifting along feature axis 0 by 2 x + x^2 and along axis 1 by y, noise 0.3 in each
// of 6 axes (RMS 0.73); the patches are groups 0 and 1, as k-means keeps them apart. Material B
// (group 2) in the same patches with the same drift, offset by `offset` along axis 2, which the
// drift never touches.
struct Scene {
  Eigen::MatrixXd features;
  Eigen::MatrixX2d field;
  std::vector<int> label;
};

Scene MakeScene(double offset) {
  constexpr int kA = 2000, kB = 300, kF = 6;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> position(-1, 1);
  std::normal_distribution<double> noise(0, 0.3);
  Scene s;
  s.features.resize(kA + kB, kF);
  s.field.resize(kA + kB, 2);
  for (int i = 0; i < kA + kB; ++i) {
    const double x = (i % 2 ? 1 : -1) * (0.9 + 0.1 * position(rng)), y = position(rng);
    s.field.row(i) << 0.01 * x, 0.01 * y;  // directions' offsets are small angles
    for (int j = 0; j < kF; ++j) s.features(i, j) = noise(rng);
    s.features(i, 0) += 2 * x + x * x;
    s.features(i, 1) += y;
    if (i >= kA) s.features(i, 2) += offset;
    s.label.push_back(i >= kA ? 2 : x < 0 ? 0 : 1);
  }
  return s;
}

}  // namespace

TEST_CASE("group merge: pieces of one drifting material join, another material stays", "[pooled]") {
  const Scene s = MakeScene(4.0);  // B's offset: 13 noise sigmas, 5.5 RMS scatters
  // The drift taken out, A's halves are one blob (their offsets differ only by noise).
  CHECK(GroupSeparation(s.features, s.field, s.label, 0, 1) < 1);
  // A and B at the same positions: their offsets differ by 4 against a scatter of 0.73.
  CHECK(GroupSeparation(s.features, s.field, s.label, 0, 2) > kMergeSeparation);
  CHECK(GroupSeparation(s.features, s.field, s.label, 1, 2) > kMergeSeparation);
  // Without the field (every pixel at one position) the patches lie 4 apart by the drift alone
  // (0.73 scatter): the rule before the drift was taken out kept them.
  const Eigen::MatrixX2d nowhere = Eigen::MatrixX2d::Zero(s.field.rows(), 2);
  CHECK(GroupSeparation(s.features, nowhere, s.label, 0, 1) > kMergeSeparation);
  // ... and the merge keeps all three: a field of no extent has no boundary to join them at.
  std::vector<int> unmerged = s.label;
  CHECK(MergeOverlapping(s.features, nowhere, 3, &unmerged) == 3);

  std::vector<int> label = s.label;
  REQUIRE(MergeOverlapping(s.features, s.field, 3, &label) == 2);
  CHECK(label[0] != label.back());
  for (std::size_t i = 0; i + 300 < label.size(); ++i) REQUIRE(label[i] == label[0]);
  for (std::size_t i = label.size() - 300; i < label.size(); ++i) REQUIRE(label[i] == label.back());
}

TEST_CASE("group merge: degenerate groups", "[pooled]") {
  Scene s = MakeScene(4.0);
  // A group of one pixel has no scatter: it is never merged, and nothing is NaN.
  s.label[5] = 3;
  const double single = GroupSeparation(s.features, s.field, s.label, 3, 0);
  CHECK(!(single < kMergeSeparation));
  // An empty group is infinitely far from any other.
  CHECK(GroupSeparation(s.features, s.field, s.label, 0, 4) > 1e300);
  std::vector<int> label = s.label;
  const int groups = MergeOverlapping(s.features, s.field, 4, &label);
  CHECK(groups == 3);
  for (int l : label) REQUIRE((l >= 0 && l < groups));
}

namespace {

// One field, [-1, 1]^2, cut at x = 0 into groups 0 (left) and 1 (right), which touch. Features in
// 6 axes with noise 0.3 each, drifting along axis 0 by 4 tanh(5 x): a ramp no quadratic follows,
// so the groups' offsets take part of it. The right half is offset by `step` along axis 2 (a
// second material beside the first when step > 0).
Scene SideBySide(double step) {
  constexpr int kPixels = 3000, kF = 6;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> position(-1, 1);
  std::normal_distribution<double> noise(0, 0.3);
  Scene s;
  s.features.resize(kPixels, kF);
  s.field.resize(kPixels, 2);
  for (int i = 0; i < kPixels; ++i) {
    const double x = position(rng), y = position(rng);
    s.field.row(i) << 0.01 * x, 0.01 * y;
    for (int j = 0; j < kF; ++j) s.features(i, j) = noise(rng);
    s.features(i, 0) += 4 * std::tanh(5 * x);
    if (x > 0) s.features(i, 2) += step;
    s.label.push_back(x < 0 ? 0 : 1);
  }
  return s;
}

}  // namespace

TEST_CASE("group merge: groups that meet without a step join, a step keeps them apart",
          "[pooled]") {
  const Scene one = SideBySide(0);
  // The quadratic drift leaves the halves of the ramp apart: the first rule alone keeps them.
  CHECK(GroupSeparation(one.features, one.field, one.label, 0, 1) > kMergeSeparation);
  const std::vector<std::vector<int>> near = FieldNeighbours(one.field);
  const BoundaryStep smooth = StepAtBoundary(one.features, one.field, near, one.label, 0, 1);
  // The boundary is a line through 3,000 pixels: far more than the minimum lie on it.
  CHECK(smooth.pixels >= kMinBoundaryPixels);
  // No step: across the boundary as within a group, up to the noise of a median (about 10%).
  CHECK(smooth.ratio < 1.2);
  std::vector<int> label = one.label;
  CHECK(MergeOverlapping(one.features, one.field, 2, &label) == 1);

  // A step of 2.5 along an axis the drift leaves alone: 2.4 times the features' distance between
  // two neighbours (sqrt(2 x 6) x 0.3 = 1.04), so about sqrt(1 + 2.4^2) = 2.6 across.
  const Scene two = SideBySide(2.5);
  CHECK(GroupSeparation(two.features, two.field, two.label, 0, 1) > kMergeSeparation);
  const BoundaryStep jump = StepAtBoundary(two.features, two.field, near, two.label, 0, 1);
  CHECK(jump.ratio > 2.0);
  label = two.label;
  CHECK(MergeOverlapping(two.features, two.field, 2, &label) == 2);

  // Not tested, because it fails: without noise and with a drift 7 times steeper across the
  // boundary than along it, a neighbour of its own group as far away differs less than one across
  // (1.46), and such pieces stay apart (docs/reconstruction.md, "Choosing the groups").
  // Groups that do not meet have no boundary to judge.
  Scene apart = SideBySide(0);
  for (int i = 0; i < int(apart.label.size()); ++i)
    if (std::abs(apart.field(i, 0)) < 0.003) apart.label[std::size_t(i)] = 2;
  const BoundaryStep none =
      StepAtBoundary(apart.features, apart.field, FieldNeighbours(apart.field), apart.label, 0, 1);
  CHECK(none.pixels == 0);
  CHECK(std::isnan(none.ratio));
  // A field of no extent (a field of view of 0) has no neighbours and so no boundary.
  const Eigen::MatrixX2d nowhere = Eigen::MatrixX2d::Zero(one.field.rows(), 2);
  for (const std::vector<int>& n : FieldNeighbours(nowhere)) REQUIRE(n.empty());
}

TEST_CASE("two labellings are the same grouping whatever the groups' numbers", "[pooled]") {
  CHECK(SameGrouping({0, 0, 1, 2, 1}, {2, 2, 0, 1, 0}));
  CHECK(SameGrouping({}, {}));
  // One group cut in two, two groups joined, a pixel moved, different lengths: not the same.
  CHECK_FALSE(SameGrouping({0, 0, 1, 1}, {0, 2, 1, 1}));
  CHECK_FALSE(SameGrouping({0, 1, 2, 2}, {0, 0, 1, 1}));
  CHECK_FALSE(SameGrouping({0, 0, 1, 1}, {0, 1, 1, 1}));
  CHECK_FALSE(SameGrouping({0, 0, 1}, {0, 0, 1, 1}));
}
