// Per-pixel SVBRDF reconstruction (Yu et al. Sec. 3.1): every reference pixel is solved on its
// own, with the basis rows, mean, reference and cos weight at the light and view directions that
// pixel really saw in each view (the near-field effect), and a ridge solve shared by its three
// colour channels. Observations are dropped per pixel, never per view: a saturated highlight or
// an occluded view costs only the pixels it touches.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "brdf/basis.h"
#include "brdf/basis_rows.h"

namespace acq {

// A tile of pixels x views, pixel-major. Directions in the sample frame, unit, pointing away
// from the surface. Values are BRDF values (1/sr) per channel; NaN marks a missing observation
// (saturated, occluded, out of frame).
struct PixelObservations {
  int pixels = 0, views = 0;
  int width = 0;  // pixels per image row in this tile (0: unknown; rows cannot be shared)
  std::vector<Eigen::Vector3f> light, camera;  // pixels * views
  std::vector<float> rgb;                      // pixels * views * 3

  void Resize(int pixels, int views);
  std::size_t At(int pixel, int view) const { return std::size_t(pixel) * views + view; }
  // The given pixels' observations, in that order (width 0: they share no rows).
  PixelObservations Gather(const std::vector<int>& which) const;
};

// Where a reconstruction's observations come from, one band of reference-view rows at a time:
// correspondence maps and HDR frames of a session, or a synthetic scene.
class ObservationSource {
 public:
  virtual ~ObservationSource() = default;
  virtual int Width() const = 0;
  virtual int Height() const = 0;
  virtual double PixelSizeMm() const = 0;
  virtual std::string Describe() const = 0;
  // Observations of rows [y0, y0 + rows), pixel (x, y) at index (y - y0) * Width() + x.
  virtual PixelObservations Rows(int y0, int rows) = 0;
  // Observations of the given pixels (y * Width() + x, increasing), in that order: by default
  // read band by band through Rows; a source that can reach single pixels cheaply overrides it
  // (the pooled reconstruction's sample is a few thousand pixels of millions).
  virtual PixelObservations Pixels(const std::vector<std::size_t>& indices, int band_rows);
};

// The condition number of rows Q from their normal matrix Q^T Q (lower triangle used), as the
// per-pixel solve estimates it: the square root of the ratio of its extreme eigenvalues, by power
// and inverse iteration. Infinite when Q^T Q is not positive definite.
double EstimateConditionNumber(const Eigen::MatrixXd& normal);

// The iteration both condition estimators run (ConditionEstimator and PixelBatch's, in lanes).
struct ConditionIteration {
  // Power steps, then as many inverse steps at most. Most estimates settle within a few (warm
  // starts from the neighbouring pixel); the cap matters where the start is nearly orthogonal
  // to the extreme eigenvector: the quotient then first settles towards the next eigenvalue and
  // climbs off it only by the ratio of the two a step. Measured on a pixel of a 10-degree card
  // (eigenvalues 3,362 and 2,251, started cold): 12 steps estimated its condition 16% low,
  // 40 steps exactly (tests/test_pixel_solver.cpp, lanes against one pixel).
  static constexpr int kMaxSteps = 40;
  static constexpr double kSettled = 1e-5;  // stop: the Rayleigh quotient moved by this, relative
};

// The same for a sequence of matrices (the pixels of a worker, one after another): each
// estimate starts from the previous matrix's extreme eigenvectors, which neighbouring pixels
// nearly share, and iterates until the Rayleigh quotients settle (ConditionIteration).
class ConditionEstimator {
 public:
  // `llt`: the Cholesky factor of `a` (computed by the caller, who needs it anyway). Returns
  // the condition number of the rows (the square root of a's eigenvalue ratio).
  double Estimate(const Eigen::MatrixXd& a, const Eigen::LLT<Eigen::MatrixXd>& llt);
  int last_steps() const { return steps_; }  // power plus inverse steps of the last estimate
  void Reset() { largest_.resize(0); }       // the next estimate starts cold

 private:
  Eigen::VectorXd largest_, smallest_, w_;
  int steps_ = 0;
};

// How rows-per-pixel solves run (row_tile 1): the same algorithm either way.
enum class PixelKernel {
  kLanesDouble,  // 8 pixels at a time across SIMD lanes, float64 (pixel_batch.h); the default
  kLanesSingle,  // 16 at a time, float32: the precision trade-off, charted in the benchmark
  kOnePixel,     // one pixel at a time with Eigen's dynamic-size routines (the reference)
};

// What a solve reports as its residual (PixelSolution::residual).
enum class ResidualKind {
  kFit,  // the RMS misfit at the observations the coefficients were fitted to
  // The RMS of each observation's exact leave-one-view-out error, r_v / (1 - h_v) with h_v the
  // ridge's hat value (the three channels share the rows, so one h_v a view): how well the
  // pixel's model predicts a view it did not see. For choosing between models of one pixel
  // (normal_search.h), where the fit's misfit rewards whatever lets the coefficients bend.
  kLeaveOneViewOut,
};

struct PixelSolveOptions {
  int components = kDefaultComponents;  // k
  double eta = kDefaultEta;
  RowLookup lookup = RowLookup::kNearest;
  int min_observations = 0;  // fewer and the pixel is invalid; 0 means k / 2
  // Pixels whose sampled rows are worse conditioned than this are still solved but not valid:
  // the ridge keeps them finite, not trustworthy.
  double max_condition = 1e4;
  // 1: every pixel its own rows (exact near field). T > 1: the pixels of each T x T tile share
  // the rows, mean, reference and cos weight at the tile centre's directions, and one
  // factorisation: T^2 times fewer, at the cost of the near-field error within a tile.
  // Default 1, the exact model: since the solves run in SIMD lanes, tiles that stay within 0.5%
  // of its error (8 x 8 and smaller; 16 leaves it at 4 degrees) save no time worth the name
  // (tools/bench_reconstruction_tradeoffs.py; at 1024 x 1024: 0.80-0.87 s per pixel, 0.80-0.82
  // s in 8 x 8 tiles; docs/reconstruction.md).
  int row_tile = 1;
  PixelKernel kernel = PixelKernel::kLanesDouble;
  ResidualKind residual = ResidualKind::kFit;
  void Check(const BasisView& basis) const;  // throws UserError
  int MinObservations() const {
    return min_observations > 0 ? min_observations : (components + 1) / 2;
  }
};

// Per-pixel results, pixel-major; coefficients are k per channel, R then G then B.
struct PixelSolution {
  int components = 0;
  std::vector<float> coefficients;          // pixels * 3 * k
  std::vector<std::uint8_t> valid;          // 1 when trustworthy
  std::vector<std::uint16_t> observations;  // views used
  std::vector<float> condition;  // of the pixel's sampled rows, n x k (inf when dependent)
  std::vector<float> residual;   // RMS log-space misfit at the observations (options.residual)
  // The pooled solve's (pooled_solver.h): the pixel's group, -1 when it was solved alone, and
  // the RMS log-space distance of its BRDF from its (or the nearest) group's centre.
  std::vector<std::int16_t> group;
  std::vector<float> departure;

  void Resize(int pixels, int k);
  // Pixel i of `part` (same k) becomes pixel where[i] of this solution: the inverse of
  // PixelObservations::Gather, for pixels solved again on their own.
  void Scatter(const PixelSolution& part, const std::vector<int>& where);
};

// Solves every pixel of the tile (OpenMP across pixels). Never writes NaN: a pixel with no
// usable observation gets zero coefficients (the mean BRDF) and valid = 0.
void SolvePixels(const BasisView& basis, const PixelObservations& observations,
                 const PixelSolveOptions& options, PixelSolution* solution, int first_pixel = 0);

}  // namespace acq
