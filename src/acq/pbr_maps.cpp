#include "acq/pbr_maps.h"

#include <Eigen/Core>
#include <algorithm>
#include <chrono>

#include "acq/map_render.h"
#include "brdf/log_mapping.h"
#include "core/progress.h"

namespace acq {
namespace {

// The basis at the fit grid's bins, gathered once: rows (bins x k), mean and reference.
struct GridBasis {
  Eigen::MatrixXf q;
  Eigen::VectorXf mean, ref;
};

GridBasis Gather(const BasisView& basis, const PbrFitGrid& grid, int k) {
  GridBasis g;
  g.q.resize(Eigen::Index(grid.Size()), k);
  g.mean.resize(Eigen::Index(grid.Size()));
  g.ref.resize(Eigen::Index(grid.Size()));
  for (std::size_t n = 0; n < grid.Size(); ++n) {
    const float* row = basis.Row(grid.bins[n]);
    for (int j = 0; j < k; ++j) g.q(Eigen::Index(n), j) = row[j];
    g.mean(Eigen::Index(n)) = basis.mean[grid.bins[n]];
    g.ref(Eigen::Index(n)) = basis.ref[grid.bins[n]];
  }
  return g;
}

}  // namespace

PbrMaps FitPbrMaps(const SvbrdfMap& map, const BasisView& basis, const PbrFitOptions& options,
                   bool progress) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  const int w = map.info.width, h = map.info.height, k = map.info.components;
  const PbrFitGrid grid =
      PbrFitGrid::Default(basis.valid, options.max_zenith_deg * 3.14159265358979323846 / 180);
  const GridBasis g = Gather(basis, grid, k);
  PbrMaps maps;
  maps.width = w;
  maps.height = h;
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  maps.parameters.resize(pixels);
  maps.log_rmse.assign(pixels, 0.0f);
  maps.converged.assign(pixels, 0);
  maps.valid.assign(pixels, 0);
  Progress bar("export pbr: fitting pixels", std::size_t(h), progress);
#pragma omp parallel
  {
    Eigen::MatrixXf coefficients(k, 3), y(Eigen::Index(grid.Size()), 3);
    std::vector<float> target(3 * grid.Size());
#pragma omp for schedule(dynamic, 1)
    for (int py = 0; py < h; ++py) {
      for (int px = 0; px < w; ++px) {
        const std::size_t p = std::size_t(py) * w + px;
        for (int c = 0; c < 3; ++c) {
          const std::vector<float> v = map.Coefficients(px, py, c);
          for (int j = 0; j < k; ++j) coefficients(j, c) = v[j];
        }
        y.noalias() = g.q * coefficients;
        for (std::size_t n = 0; n < grid.Size(); ++n)
          for (int c = 0; c < 3; ++c)
            target[3 * n + c] =
                float(std::max(UnmapBrdf(y(Eigen::Index(n), c) + g.mean(Eigen::Index(n)),
                                         grid.cos_weight[n], g.ref(Eigen::Index(n))),
                               0.0));
        const PbrFit fit = FitPbr(grid, target.data(), options);
        maps.parameters[p] = fit.parameters;
        maps.log_rmse[p] = float(fit.log_rmse);
        maps.converged[p] = fit.converged;
        maps.valid[p] = map.Plane("valid", px, py) > 0;
      }
      bar.Tick();
    }
  }
  maps.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return maps;
}

PixelBrdf PbrPixelBrdf(const PbrMaps& maps) {
  return [&maps](int x, int y, const Eigen::Vector3d& in, const Eigen::Vector3d& out) {
    return EvaluatePbr(maps.parameters[std::size_t(y) * maps.width + x], in, out);
  };
}

}  // namespace acq
