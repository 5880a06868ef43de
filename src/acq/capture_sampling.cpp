#include "acq/capture_sampling.h"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace acq {
namespace {

struct Grid {
  int width, height;
  std::size_t At(int x, int y) const {
    return std::size_t(y) * std::size_t(width) + std::size_t(x);
  }
  bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

struct Corner {
  int x, y;
  double weight;
};

// The four grid points around point (u, v) and their bilinear weights: the rule the capture is
// read by (correspondence_source.cpp, Sample; a pixel's centre at integer coordinates).
std::array<Corner, 4> BilinearCorners(double u, double v) {
  const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
  std::array<Corner, 4> corners;
  for (int k = 0; k < 4; ++k) {
    const int x = x0 + k % 2, y = y0 + k / 2;
    corners[std::size_t(k)] = {x, y, (1 - std::abs(u - x)) * (1 - std::abs(v - y))};
  }
  return corners;
}

// The view position of reference pixel (x, y), if known.
std::optional<Eigen::Vector2d> PositionAt(const Grid& g, const CapturePositions& p, int x, int y) {
  if (!g.Inside(x, y)) return std::nullopt;
  const std::size_t i = g.At(x, y);
  if (!std::isfinite(p.x[i]) || !std::isfinite(p.y[i])) return std::nullopt;
  return Eigen::Vector2d(p.x[i], p.y[i]);
}

// d(view position) / d(reference pixel) along (dx, dy): central where both neighbours are known,
// one-sided at an edge or beside a pixel not read.
std::optional<Eigen::Vector2d> Derivative(const Grid& g, const CapturePositions& p, int x, int y,
                                          int dx, int dy) {
  const auto before = PositionAt(g, p, x - dx, y - dy), after = PositionAt(g, p, x + dx, y + dy);
  if (before && after) return (*after - *before) / 2;
  const auto here = PositionAt(g, p, x, y);
  if (!here) return std::nullopt;
  if (after) return *after - *here;
  if (before) return *here - *before;
  return std::nullopt;
}

// The prediction at reference point (u, v) by the bilinear rule the capture's sampling uses,
// over the known pixels among the four around it; none when none is known or it is off the grid.
std::optional<std::array<double, 3>> Bilinear(const Grid& g, const std::vector<float>& values,
                                              const std::vector<std::uint8_t>& known, double u,
                                              double v) {
  if (!(u >= 0 && v >= 0 && u <= g.width - 1 && v <= g.height - 1)) return std::nullopt;
  std::array<double, 3> sum{};
  double weight = 0;
  for (const Corner& k : BilinearCorners(u, v)) {
    if (k.weight <= 0 || !g.Inside(k.x, k.y) || !known[g.At(k.x, k.y)]) continue;
    for (int c = 0; c < 3; ++c)
      sum[std::size_t(c)] += k.weight * values[3 * g.At(k.x, k.y) + std::size_t(c)];
    weight += k.weight;
  }
  // A point whose only known neighbour weighs next to nothing is not predicted from it.
  constexpr double kMinWeight = 1e-3;
  if (weight < kMinWeight) return std::nullopt;
  for (double& s : sum) s /= weight;
  return sum;
}

// Reference pixel (x, y) sampled as the capture was, or none (see the header).
std::optional<std::array<double, 3>> AsCaptured(const Grid& g, const CapturePositions& p,
                                                const std::vector<float>& values,
                                                const std::vector<std::uint8_t>& known, int x,
                                                int y) {
  const auto at = PositionAt(g, p, x, y);
  if (!at) return std::nullopt;
  const auto du = Derivative(g, p, x, y, 1, 0), dv = Derivative(g, p, x, y, 0, 1);
  if (!du || !dv) return std::nullopt;
  Eigen::Matrix2d jacobian;
  jacobian << *du, *dv;
  constexpr double kMinDeterminant = 1e-6;  // view pixels per reference pixel, squared
  if (!(std::abs(jacobian.determinant()) > kMinDeterminant)) return std::nullopt;
  const Eigen::Matrix2d reference_from_view = jacobian.inverse();
  std::array<double, 3> sum{};
  for (const Corner& view_pixel : BilinearCorners(at->x(), at->y())) {
    if (view_pixel.weight <= 0) continue;
    const Eigen::Vector2d point =
        Eigen::Vector2d(x, y) +
        reference_from_view * (Eigen::Vector2d(view_pixel.x, view_pixel.y) - *at);
    const auto value = Bilinear(g, values, known, point.x(), point.y());
    if (!value) return std::nullopt;
    for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += view_pixel.weight * (*value)[std::size_t(c)];
  }
  return sum;
}

}  // namespace

std::vector<float> SampleAsCaptured(int width, int height, const CapturePositions& positions,
                                    const std::vector<float>& predicted,
                                    const std::vector<std::uint8_t>& known) {
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  if (positions.x.size() != pixels || positions.y.size() != pixels ||
      predicted.size() != 3 * pixels || known.size() != pixels)
    throw std::invalid_argument("SampleAsCaptured: positions, prediction and flags of other sizes");
  const Grid g{width, height};
  std::vector<float> out = predicted;
#pragma omp parallel for schedule(dynamic, 4)
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t i = g.At(x, y);
      if (!known[i]) continue;
      if (const auto value = AsCaptured(g, positions, predicted, known, x, y))
        for (int c = 0; c < 3; ++c) out[3 * i + std::size_t(c)] = float((*value)[std::size_t(c)]);
    }
  return out;
}

}  // namespace acq
