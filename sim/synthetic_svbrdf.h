// Synthetic SVBRDF scenes and the observations a capture of them would give, straight from the
// ground truth (no camera simulation): the inputs the reconstruction is tested and benchmarked
// on until real correspondence maps exist.
//
// The reference view looks straight down at the sample centre; reference pixel (x, y) is the
// centre of cell (x, y) of the sample's grid (core/sample_grid.h: columns along the sample
// frame's x, rows along its -y, as a session's reference camera sees it). Each view is a pair of
// arm poses at the near-field geometry's distances; a pixel's light and view directions are those
// from its own point.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "brdf/neural_brdf.h"
#include "brdf/pixel_solver.h"
#include "core/gantry_geometry.h"
#include "core/sample_grid.h"

namespace acq::sim {

struct SyntheticSvbrdf {
  int width = 0, height = 0;
  double sample_size_mm = 0;        // the width the reference view covers; cells are square
  std::vector<std::uint8_t> label;  // material index per pixel, row-major
  // The true shading normal per pixel in the sample frame (relief.h); empty: flat. A pixel's
  // material is evaluated in its facet's frame (core/facet_frame.h).
  std::vector<Eigen::Vector3f> normal;
  SampleGrid Grid() const;  // the cells as laid on the sample plane
  Eigen::Vector2d PointOf(int pixel) const;
  // The material under a sample-plane point (mm, the card centred at the origin): the label of
  // the cell it falls in, -1 off the card. The one rule the renderer and the scoring share.
  int LabelAt(const Eigen::Vector2d& point_mm) const;
  // The true normal at that point, by the same cell rule: +z off the card or without relief.
  Eigen::Vector3f NormalAt(const Eigen::Vector2d& point_mm) const;
};

// A printed card: a background material, two rectangles with sharp edges, and strokes of "text"
// (thin bars, one pixel and up) in the remaining materials. Deterministic for a seed.
SyntheticSvbrdf MakeCardLayout(int width, int height, double sample_size_mm, int materials,
                               std::uint64_t seed);

// A ground-truth material: the neural fit evaluated at the exact directions (continuous), or its
// MERL table read at the nearest bin (what the basis and the closed-form evaluator see).
struct GroundTruth {
  const NeuralBrdf* network = nullptr;
  const MerlBrdf* table = nullptr;
  // A mixed material (sample_layouts.h): the weighted sum of these truths' values; network and
  // table are then unused.
  std::vector<std::pair<const GroundTruth*, double>> mix;
  std::array<double, 3> Value(const DirectionPair& d) const;
  // Its value at a tilted facet of normal n (sample frame) under sample-frame directions d,
  // measured as if the sample were flat: the BRDF in the facet's frame times n.l / l.z
  // (core/facet_frame.h), a fit's slightly negative value taken as none. A light the facet turns
  // away from, or a camera it hides from, gives zero: the facet is dark there (what a camera
  // records), not unobserved. The one rule the renderer and the synthetic observations share.
  std::array<double, 3> ValueOnFacet(const Eigen::Vector3f& n, const DirectionPair& d) const;
};

struct ObservationOptions {
  NearFieldGeometry geometry;  // distances; sample_size_mm is taken from the scene
  // Attach the centre's directions to every pixel (the values still come from its true ones):
  // what a reconstruction that ignores the near field does.
  bool centre_directions = false;
  double noise_sigma = 0;  // multiplicative Gaussian noise on the BRDF values (relative)
  std::uint64_t seed = 1;
};

// Observations of pixels [first, first + count) in every view: each material's value at the
// pixel's true directions; views where a pixel sees below the horizon are missing.
PixelObservations SyntheticObservations(const SyntheticSvbrdf& scene,
                                        const std::vector<GroundTruth>& materials,
                                        const std::vector<ArmAngles>& views,
                                        const ObservationOptions& options, int first, int count);
// The same for any pixels (indices into the scene, y * width + x), in the given order.
PixelObservations SyntheticObservationsAt(const SyntheticSvbrdf& scene,
                                          const std::vector<GroundTruth>& materials,
                                          const std::vector<ArmAngles>& views,
                                          const ObservationOptions& options,
                                          const std::vector<std::size_t>& pixels);

// A synthetic scene as an observation source for the reconstruction job.
class SyntheticSource : public ObservationSource {
 public:
  SyntheticSource(SyntheticSvbrdf scene, std::vector<GroundTruth> materials,
                  std::vector<ArmAngles> views, ObservationOptions options)
      : scene_(std::move(scene)),
        materials_(std::move(materials)),
        views_(std::move(views)),
        options_(options) {}
  int Width() const override { return scene_.width; }
  int Height() const override { return scene_.height; }
  double PixelSizeMm() const override { return scene_.sample_size_mm / scene_.width; }
  std::string Describe() const override;
  PixelObservations Rows(int y0, int rows) override {
    return SyntheticObservations(scene_, materials_, views_, options_, y0 * scene_.width,
                                 rows * scene_.width);
  }
  PixelObservations Pixels(const std::vector<std::size_t>& indices, int) override {
    return SyntheticObservationsAt(scene_, materials_, views_, options_, indices);
  }
  const SyntheticSvbrdf& scene() const { return scene_; }

 private:
  SyntheticSvbrdf scene_;
  std::vector<GroundTruth> materials_;
  std::vector<ArmAngles> views_;
  ObservationOptions options_;
};

}  // namespace acq::sim
