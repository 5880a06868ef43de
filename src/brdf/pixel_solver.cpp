#include "brdf/pixel_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "brdf/log_mapping.h"
#include "brdf/pixel_batch.h"
#include "brdf/pixel_rows.h"
#include "core/error.h"

namespace acq {

void PixelObservations::Resize(int p, int v) {
  pixels = p;
  views = v;
  light.assign(std::size_t(p) * v, Eigen::Vector3f::UnitZ());
  camera.assign(std::size_t(p) * v, Eigen::Vector3f::UnitZ());
  rgb.assign(std::size_t(p) * v * 3, std::numeric_limits<float>::quiet_NaN());
}

PixelObservations PixelObservations::Gather(const std::vector<int>& which) const {
  PixelObservations out;
  out.Resize(int(which.size()), views);
  for (std::size_t i = 0; i < which.size(); ++i) {
    const std::size_t from = At(which[i], 0), to = out.At(int(i), 0);
    std::copy_n(&light[from], views, &out.light[to]);
    std::copy_n(&camera[from], views, &out.camera[to]);
    std::copy_n(&rgb[3 * from], 3 * views, &out.rgb[3 * to]);
  }
  return out;
}

PixelObservations ObservationSource::Pixels(const std::vector<std::size_t>& indices,
                                            int band_rows) {
  const int w = Width(), h = Height();
  PixelObservations out;
  std::size_t next = 0;
  for (int y0 = 0; y0 < h && next < indices.size(); y0 += band_rows) {
    const int rows = std::min(band_rows, h - y0);
    const std::size_t end = std::size_t(y0 + rows) * w;
    if (indices[next] >= end) continue;  // no pixel wanted in this band
    const PixelObservations obs = Rows(y0, rows);
    out.views = obs.views;
    for (; next < indices.size() && indices[next] < end; ++next) {
      const int p = int(indices[next] - std::size_t(y0) * w);
      for (int v = 0; v < obs.views; ++v) {
        const std::size_t i = obs.At(p, v);
        out.light.push_back(obs.light[i]);
        out.camera.push_back(obs.camera[i]);
        out.rgb.insert(out.rgb.end(), &obs.rgb[3 * i], &obs.rgb[3 * i] + 3);
      }
      ++out.pixels;
    }
  }
  return out;
}

void PixelSolution::Resize(int pixels, int k) {
  components = k;
  coefficients.assign(std::size_t(pixels) * 3 * k, 0.0f);
  valid.assign(pixels, 0);
  observations.assign(pixels, 0);
  condition.assign(pixels, 0.0f);
  residual.assign(pixels, 0.0f);
  group.assign(pixels, -1);
  departure.assign(pixels, 0.0f);
}

void PixelSolution::Scatter(const PixelSolution& part, const std::vector<int>& where) {
  const std::size_t k3 = 3 * std::size_t(components);
  for (std::size_t i = 0; i < where.size(); ++i) {
    const std::size_t p = std::size_t(where[i]);
    std::copy_n(&part.coefficients[i * k3], k3, &coefficients[p * k3]);
    valid[p] = part.valid[i];
    observations[p] = part.observations[i];
    condition[p] = part.condition[i];
    residual[p] = part.residual[i];
    group[p] = part.group[i];
    departure[p] = part.departure[i];
  }
}

void PixelSolveOptions::Check(const BasisView& basis) const {
  if (components < 1 || components > basis.components)
    throw UserError("--k", "must be in [1, " + std::to_string(basis.components) + "]");
  if (!(eta >= 0)) throw UserError("--eta", "must be >= 0", "the papers use 40");
  if (min_observations < 0) throw UserError("--min-observations", "must be >= 0");
  if (row_tile < 1 || row_tile > 1024) throw UserError("--row-tile", "must be in [1, 1024]");
}

// Extreme eigenvalues of a symmetric positive definite matrix by power iteration and inverse
// iteration, measured by their Rayleigh quotients. A Rayleigh quotient's error is second order in
// the iterate's error, so from a cold start a dozen steps give the condition number to well
// under a percent on these 20 x 20 normal matrices (checked against a full eigendecomposition in
// the tests), at a fraction of the cost of one: the eigensolver was the largest single cost of
// the per-pixel solve. From the previous pixel's eigenvectors two or three steps do; iteration
// stops once a step changes the quotient by under 1e-5 of it (a slowly converging iteration
// means nearly equal eigenvalues, whose quotient is then already close).
double ConditionEstimator::Estimate(const Eigen::MatrixXd& a,
                                    const Eigen::LLT<Eigen::MatrixXd>& llt) {
  constexpr int kMaxSteps = ConditionIteration::kMaxSteps;
  constexpr double kSettled = ConditionIteration::kSettled;
  const Eigen::Index k = a.rows();
  if (largest_.size() != k) {
    largest_.setConstant(k, 1.0 / std::sqrt(double(k)));
    smallest_ = largest_;
  }
  steps_ = 0;
  double largest = 0;
  for (int i = 0; i < kMaxSteps; ++i) {
    ++steps_;
    w_.noalias() = a.selfadjointView<Eigen::Lower>() * largest_;
    const double q = largest_.dot(w_);
    largest_ = w_ / w_.norm();
    const bool settled = i > 0 && std::abs(q - largest) <= kSettled * q;
    largest = q;
    if (settled) break;
  }
  // Inverse iteration: the Rayleigh quotient of A^-1 is 1 / (the smallest eigenvalue of A).
  double inverse = 0;
  for (int i = 0; i < kMaxSteps; ++i) {
    ++steps_;
    w_ = llt.solve(smallest_);
    const double q = smallest_.dot(w_);
    smallest_ = w_ / w_.norm();
    const bool settled = i > 0 && std::abs(q - inverse) <= kSettled * q;
    inverse = q;
    if (settled) break;
  }
  if (!std::isfinite(largest) || !std::isfinite(inverse) || largest <= 0 || inverse <= 0) {
    largest_.resize(0);  // start cold next time
    return std::numeric_limits<double>::infinity();
  }
  return std::sqrt(largest * inverse);
}

double EstimateConditionNumber(const Eigen::MatrixXd& normal) {
  Eigen::LLT<Eigen::MatrixXd> llt(normal);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return ConditionEstimator().Estimate(normal, llt);
}

// Work units handed to a thread at a time (OpenMP's dynamic chunks start at multiples of it).
constexpr int kChunk = 16;

namespace {

// The one-pixel path: a pixel's solve from rows sampled into `rows` (its own, or its tile's).
// Buffers live as long as the worker thread, so a pixel allocates nothing.
struct OnePixel {
  ViewRows rows;
  Factor factor;
  PixelRowMatrix q;
  Eigen::MatrixXd y, rhs, c, fit;
  std::vector<std::uint8_t> used;

  explicit OnePixel(int views, int k)
      : q(views, k), y(views, 3), rhs(k, 3), c(k, 3), fit(views, 3), used(views) {}

  // Samples the pixel's own rows first.
  void SolveOwn(const BasisView& basis, const PixelObservations& obs, int p,
                const PixelSolveOptions& options, PixelSolution* solution, int first_pixel) {
    rows.Sample(basis, obs, p, options.components, options.lookup);
    factor.views.clear();
    Solve(obs, p, options, solution, first_pixel);
  }

  void Solve(const PixelObservations& obs, int p, const PixelSolveOptions& options,
             PixelSolution* solution, int first_pixel) {
    const int k = options.components;
    int n = 0;
    for (int v = 0; v < obs.views; ++v) {
      const float* rgb = &obs.rgb[3 * obs.At(p, v)];
      used[v] =
          rows.ok[v] && std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2]);
      if (!used[v]) continue;
      const BasisSample& s = rows.samples[v];
      q.row(n) = rows.rows.row(v);
      for (int ch = 0; ch < 3; ++ch) y(n, ch) = MapBrdf(rgb[ch], s.cos_weight, s.ref) - s.mean;
      ++n;
    }
    const std::size_t out = std::size_t(first_pixel) + p;
    solution->observations[out] = std::uint16_t(n);
    float* coeff = &solution->coefficients[out * 3 * k];
    if (n == 0) {
      solution->valid[out] = 0;
      solution->condition[out] = std::numeric_limits<float>::infinity();
      return;
    }
    if (factor.views != used) {
      factor.Compute(q.topRows(n), k, options.eta);
      factor.views = used;
    }
    const auto qn = q.topRows(n);
    rhs.noalias() = qn.transpose() * y.topRows(n);
    c = factor.llt.solve(rhs);
    fit.noalias() = qn * c;
    double misfit = 0;
    for (int v = 0; v < n; ++v) {
      double scale = 1;  // ResidualKind::kFit
      if (options.residual == ResidualKind::kLeaveOneViewOut) {
        const double h = factor.llt.matrixL().solve(qn.row(v).transpose()).squaredNorm();
        scale = 1 / std::max(1 - h, 1e-12);
      }
      misfit += scale * scale * (fit.row(v) - y.row(v)).squaredNorm();
    }
    const bool finite = c.allFinite() && std::isfinite(misfit);
    for (int ch = 0; ch < 3; ++ch)
      for (int j = 0; j < k; ++j) coeff[ch * k + j] = finite ? float(c(j, ch)) : 0.0f;
    solution->condition[out] = float(factor.condition);
    solution->residual[out] = finite ? float(std::sqrt(misfit / (3.0 * n))) : 0.0f;
    solution->valid[out] =
        finite && n >= options.MinObservations() && factor.condition <= options.max_condition;
  }
};

// Rows per pixel, kLanes<T> pixels a work unit (pixel_batch.h); a pixel the batch defers
// (fewer usable observations than k) goes the one-pixel way.
template <class T>
void SolveInLanes(const BasisView& basis, const PixelObservations& obs,
                  const PixelSolveOptions& options, PixelSolution* solution, int first_pixel) {
  constexpr int kWidth = PixelBatch<T>::kWidth;
  const int units = (obs.pixels + kWidth - 1) / kWidth;
#pragma omp parallel
  {
    PixelBatch<T> batch;
    OnePixel one(obs.views, options.components);
#pragma omp for schedule(dynamic, kChunk)
    for (int t = 0; t < units; ++t) {
      if (t % kChunk == 0) {  // warm starts within a chunk only: see SolvePixels
        batch.ColdStart();
        one.factor.estimator.Reset();
      }
      const int first = t * kWidth, count = std::min(kWidth, obs.pixels - first);
      batch.Load(basis, obs, first, count, options.components, options.lookup);
      for (int l = 0; l < count; ++l)
        if (batch.Deferred(l)) one.SolveOwn(basis, obs, first + l, options, solution, first_pixel);
      batch.Solve(options, solution, std::size_t(first_pixel) + first);
    }
  }
}

}  // namespace

void SolvePixels(const BasisView& basis, const PixelObservations& obs,
                 const PixelSolveOptions& options, PixelSolution* solution, int first_pixel) {
  options.Check(basis);
  const int k = options.components;
  // Work units: single pixels, or tiles of row_tile x row_tile pixels that share the rows of
  // their centre pixel (the band's width says where rows of pixels wrap).
  const int tile = obs.width > 0 ? options.row_tile : 1;
  if (tile == 1 && options.kernel == PixelKernel::kLanesDouble)
    return SolveInLanes<double>(basis, obs, options, solution, first_pixel);
  if (tile == 1 && options.kernel == PixelKernel::kLanesSingle)
    return SolveInLanes<float>(basis, obs, options, solution, first_pixel);
  const int width = obs.width > 0 ? obs.width : obs.pixels;
  const int height = (obs.pixels + width - 1) / width;
  const int tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
#pragma omp parallel
  {
    OnePixel one(obs.views, k);
#pragma omp for schedule(dynamic, kChunk)
    for (int t = 0; t < tiles_x * tiles_y; ++t) {
      // Warm starts run within a chunk, whose order is fixed, never across chunks, whose
      // assignment to threads is not: the map is the same from run to run.
      if (t % kChunk == 0) one.factor.estimator.Reset();
      const int x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
      const int x1 = std::min(x0 + tile, width), y1 = std::min(y0 + tile, height);
      const int centre = std::min((y0 + y1) / 2 * width + (x0 + x1) / 2, obs.pixels - 1);
      if (tile > 1) {
        one.rows.Sample(basis, obs, centre, k, options.lookup);
        one.factor.views.clear();
      }
      for (int py = y0; py < y1; ++py) {
        for (int px = x0; px < x1; ++px) {
          const int p = py * width + px;
          if (p >= obs.pixels) continue;
          if (tile == 1)
            one.SolveOwn(basis, obs, p, options, solution, first_pixel);
          else
            one.Solve(obs, p, options, solution, first_pixel);
        }
      }
    }
  }
}

}  // namespace acq
