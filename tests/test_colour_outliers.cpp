// The observations a group's centre leaves out as colour fringes (brdf/colour_outliers.h), on a
// group whose colour drifts smoothly over the field as a material's does in the near field.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "brdf/colour_outliers.h"

using namespace acq;

namespace {

constexpr int kPixels = 2000, kViews = 4;
constexpr double kNoise = 0.03;  // log colour noise of every observation

// Pixels spread over a field of directions' offsets (0.01 rad across: a few degrees), with a
// colour at views 0 and 1 that drifts by 1.5 (log) from one side of the field to the other, 50
// noise sigmas: a steep near-field change, against which a group-wide median and scale would
// not see the fringe at view 0 (its robust scale would be 0.55, the limit 4.5).
// `fringe` is added to or taken from (at random, as a Bayer phase would have it) the red ratio at
// view 0 of the pixels along the field's edge x > 0.9.
struct Group {
  Eigen::MatrixX2d field;
  Eigen::MatrixXd colour;
  std::vector<bool> at_edge;
};

// spread false: every pixel at the field's centre, and no drift.
Group MakeGroup(double fringe, bool spread = true) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> position(-1, 1);
  std::normal_distribution<double> noise(0, kNoise);
  std::bernoulli_distribution sign(0.5);
  Group g;
  g.field.resize(kPixels, 2);
  g.colour.resize(kPixels, 2 * kViews);
  for (int i = 0; i < kPixels; ++i) {
    const double x = position(rng), y = position(rng);
    g.field.row(i) << (spread ? 0.005 * x : 0.0), (spread ? 0.005 * y : 0.0);
    g.at_edge.push_back(x > 0.9);
    for (int j = 0; j < 2 * kViews; ++j) g.colour(i, j) = noise(rng);
    if (spread) {  // views 0 and 1's red ratio: the drift
      g.colour(i, 0) += 0.75 * x;
      g.colour(i, 2 * 1) += 0.75 * x;
    }
    if (g.at_edge.back()) g.colour(i, 0) += sign(rng) ? fringe : -fringe;
  }
  return g;
}

// Observations left out, at the field's edge and elsewhere.
std::pair<int, int> Counts(const Group& g, const std::vector<std::uint8_t>& out, int view) {
  int edge = 0, elsewhere = 0;
  for (int i = 0; i < kPixels; ++i)
    if (out[std::size_t(i) * kViews + view]) (g.at_edge[i] ? edge : elsewhere) += 1;
  return {edge, elsewhere};
}

}  // namespace

TEST_CASE("colour outliers: a fringe is left out, a drift and the noise are kept", "[pooled]") {
  const Group g = MakeGroup(0.5);  // 17 noise sigmas: a fringe a tenth of a dark ink's edge's
  const std::vector<std::uint8_t> out = ColourOutliers(g.field, g.colour, kViews);
  int edge_pixels = 0;
  for (bool e : g.at_edge) edge_pixels += e;
  const auto [edge, elsewhere] = Counts(g, out, 0);
  INFO("edge pixels " << edge_pixels << ": left out " << edge << ", elsewhere " << elsewhere);
  // The band's pixels are fringed either way, so their neighbours' median stays near the
  // true colour: most of the band goes, and nothing outside it.
  CHECK(edge > edge_pixels / 2);
  CHECK(elsewhere == 0);
  // View 1's drift (without a fringe) is 50 sigmas over the field but a sigma or two between
  // neighbours: kept (8 robust sigmas: Gaussian noise alone would leave out one in 1e15).
  const auto [drift_edge, drift_elsewhere] = Counts(g, out, 1);
  CHECK(drift_edge + drift_elsewhere == 0);
  for (int v = 2; v < kViews; ++v) CHECK(Counts(g, out, v) == std::make_pair(0, 0));
}

TEST_CASE("colour outliers: none in a grey group, in an unseen view, or without a field",
          "[pooled]") {
  SECTION("a mono camera's channels are equal: its colour is zero everywhere") {
    const Group g = MakeGroup(0.5);
    const Eigen::MatrixXd grey = Eigen::MatrixXd::Zero(kPixels, 2 * kViews);
    for (std::uint8_t o : ColourOutliers(g.field, grey, kViews)) REQUIRE(o == 0);
  }
  SECTION("an observation not made is not an outlier") {
    Group g = MakeGroup(0.5);
    g.colour.col(0).setConstant(std::numeric_limits<double>::quiet_NaN());
    g.colour.col(1).setConstant(std::numeric_limits<double>::quiet_NaN());
    const std::vector<std::uint8_t> out = ColourOutliers(g.field, g.colour, kViews);
    CHECK(Counts(g, out, 0) == std::make_pair(0, 0));
  }
  SECTION("a field of no extent compares with the whole group at the view") {
    // Every pixel at the same directions (no drift to follow): the group's median is the
    // neighbourhood, and the fringe still stands 17 sigmas from it.
    const Group g = MakeGroup(0.5, false);  // no position, so no drift either
    const std::vector<std::uint8_t> out = ColourOutliers(g.field, g.colour, kViews);
    int edge_pixels = 0;
    for (bool e : g.at_edge) edge_pixels += e;
    const auto [edge, elsewhere] = Counts(g, out, 0);
    CHECK(edge == edge_pixels);
    CHECK(elsewhere == 0);
  }
}
