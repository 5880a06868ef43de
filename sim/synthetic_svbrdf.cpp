#include "sim/synthetic_svbrdf.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/facet_frame.h"

namespace acq::sim {

SampleGrid SyntheticSvbrdf::Grid() const {
  // Square cells, as a map's pixels are (one pixel_size_mm): the width spans the sample size.
  const double cell_mm = width > 0 ? sample_size_mm / width : 0;
  return {width, height, sample_size_mm, cell_mm * height};
}

Eigen::Vector2d SyntheticSvbrdf::PointOf(int pixel) const {
  return Grid().CentreOf(pixel % width, pixel / width);
}

namespace {

// The cell a sample-plane point falls in, row-major; -1 off the card.
long CellAt(const SyntheticSvbrdf& s, const Eigen::Vector2d& p) {
  return s.Grid().PixelAt(p);
}

}  // namespace

int SyntheticSvbrdf::LabelAt(const Eigen::Vector2d& p) const {
  const long cell = CellAt(*this, p);
  return cell < 0 ? -1 : label[std::size_t(cell)];
}

Eigen::Vector3f SyntheticSvbrdf::NormalAt(const Eigen::Vector2d& p) const {
  const long cell = normal.empty() ? -1 : CellAt(*this, p);
  return cell < 0 ? Eigen::Vector3f::UnitZ() : normal[std::size_t(cell)];
}

SyntheticSvbrdf MakeCardLayout(int width, int height, double sample_size_mm, int materials,
                               std::uint64_t seed) {
  SyntheticSvbrdf s;
  s.width = width;
  s.height = height;
  s.sample_size_mm = sample_size_mm;
  s.label.assign(std::size_t(width) * height, 0);
  std::mt19937_64 rng(seed);
  auto fill = [&](int x0, int y0, int x1, int y1, int m) {
    for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, width); ++x)
        s.label[y * width + x] = std::uint8_t(m);
  };
  if (materials > 1) fill(width / 10, height / 10, width / 2, height / 2, 1);
  if (materials > 2) fill(width / 2, height / 2, 9 * width / 10, 8 * height / 10, 2);
  // "Text": rows of short bars of varied width (down to one pixel) in the remaining materials.
  std::uniform_int_distribution<int> bar(1, std::max(1, width / 40));
  const int first_text = std::min(3, materials - 1);
  int m = first_text;
  for (int line = 0; line < 3; ++line) {
    const int y0 = height * (55 + 12 * line) / 100;
    for (int x = width / 12; x < width / 2; x += bar(rng) + 2) {
      const int w = bar(rng);
      fill(x, y0, x + w, y0 + std::max(2, height / 16), m);
      if (++m >= materials) m = first_text;
    }
  }
  return s;
}

std::array<double, 3> GroundTruth::Value(const DirectionPair& d) const {
  if (!mix.empty()) {
    std::array<double, 3> sum{};
    for (const auto& [truth, w] : mix) {
      const std::array<double, 3> v = truth->Value(d);
      for (int c = 0; c < 3; ++c) sum[c] += w * v[c];
    }
    return sum;
  }
  if (table) return table->Lookup(d.in, d.out);
  return network->Evaluate(RusinkiewiczFromDirections(d.in, d.out));
}

std::array<double, 3> GroundTruth::ValueOnFacet(const Eigen::Vector3f& n,
                                                const DirectionPair& d) const {
  return SeenAsFlat(n, d.in, d.out, [this](const Eigen::Vector3d& in, const Eigen::Vector3d& out) {
    std::array<double, 3> f = Value({in, out});
    for (double& v : f) v = std::max(v, 0.0);
    return f;
  });
}

namespace {

// Observations of count pixels, the p-th being scene pixel pixel_of(p).
template <class PixelOf>
PixelObservations Observe(const SyntheticSvbrdf& scene, const std::vector<GroundTruth>& materials,
                          const std::vector<ArmAngles>& views, const ObservationOptions& options,
                          int count, PixelOf pixel_of) {
  NearFieldGeometry g = options.geometry;
  g.sample_size_mm = scene.sample_size_mm;
  PixelObservations obs;
  obs.Resize(count, int(views.size()));
  std::vector<DirectionPair> far;  // each view's arm directions, once, not per pixel
  for (const ArmAngles& v : views) far.push_back(DirectionsOf(v));
#pragma omp parallel for schedule(dynamic, 64)
  for (int p = 0; p < count; ++p) {
    const int pixel = int(pixel_of(p));
    const Eigen::Vector2d point = scene.PointOf(pixel);
    // Noise is seeded per pixel so tiles, threads and samples give the same answer.
    std::mt19937_64 rng(options.seed * 0x9E3779B97F4A7C15ull + std::uint64_t(pixel));
    std::normal_distribution<double> noise(0.0, 1.0);
    for (std::size_t v = 0; v < views.size(); ++v) {
      const DirectionPair truth = g.DirectionsAt(far[v], point);
      const std::size_t i = obs.At(p, int(v));
      const DirectionPair label = options.centre_directions ? far[v] : truth;
      obs.light[i] = label.in.cast<float>();
      obs.camera[i] = label.out.cast<float>();
      if (!AboveHorizon(truth)) continue;  // stays NaN: missing
      // A tilted facet (relief) turned away from the light or the camera is dark, as the
      // renderer makes it (GroundTruth::ValueOnFacet).
      const GroundTruth& material = materials[scene.label[pixel]];
      const std::array<double, 3> rgb = scene.normal.empty()
                                            ? material.Value(truth)
                                            : material.ValueOnFacet(scene.normal[pixel], truth);
      for (int c = 0; c < 3; ++c)
        obs.rgb[3 * i + c] =
            float(std::max(rgb[c], 0.0) * (1.0 + options.noise_sigma * noise(rng)));
    }
  }
  return obs;
}

}  // namespace

PixelObservations SyntheticObservations(const SyntheticSvbrdf& scene,
                                        const std::vector<GroundTruth>& materials,
                                        const std::vector<ArmAngles>& views,
                                        const ObservationOptions& options, int first, int count) {
  PixelObservations obs =
      Observe(scene, materials, views, options, count, [first](int p) { return first + p; });
  // Whole rows of the image: tiles of pixels can then share rows.
  if (first % scene.width == 0 && count % scene.width == 0) obs.width = scene.width;
  return obs;
}

PixelObservations SyntheticObservationsAt(const SyntheticSvbrdf& scene,
                                          const std::vector<GroundTruth>& materials,
                                          const std::vector<ArmAngles>& views,
                                          const ObservationOptions& options,
                                          const std::vector<std::size_t>& pixels) {
  return Observe(scene, materials, views, options, int(pixels.size()),
                 [&pixels](int p) { return pixels[p]; });
}

std::string SyntheticSource::Describe() const {
  return "synthetic card " + std::to_string(scene_.width) + "x" + std::to_string(scene_.height) +
         ", " + std::to_string(materials_.size()) + " materials, " + std::to_string(views_.size()) +
         " views, sample " + std::to_string(scene_.sample_size_mm) + " mm, noise " +
         std::to_string(options_.noise_sigma) +
         (options_.centre_directions ? ", centre directions" : "");
}

}  // namespace acq::sim
