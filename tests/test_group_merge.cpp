// The merge of the pooled model's k-means groups (brdf/group_merge.h), on features made to
// drift across the field as a material's first solves do in the near field.
#include <catch2/catch.hpp>
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
