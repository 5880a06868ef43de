#include "brdf/pixel_solver.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "brdf/log_mapping.h"
#include "core/error.h"

namespace acq {

void PixelObservations::Resize(int p, int v) {
  pixels = p;
  views = v;
  light.assign(std::size_t(p) * v, Eigen::Vector3f::UnitZ());
  camera.assign(std::size_t(p) * v, Eigen::Vector3f::UnitZ());
  rgb.assign(std::size_t(p) * v * 3, std::numeric_limits<float>::quiet_NaN());
}

void PixelSolution::Resize(int pixels, int k) {
  components = k;
  coefficients.assign(std::size_t(pixels) * 3 * k, 0.0f);
  valid.assign(pixels, 0);
  observations.assign(pixels, 0);
  condition.assign(pixels, 0.0f);
  residual.assign(pixels, 0.0f);
}

void PixelSolveOptions::Check(const BasisView& basis) const {
  if (components < 1 || components > basis.components)
    throw UserError("--k", "must be in [1, " + std::to_string(basis.components) + "]");
  if (!(eta >= 0)) throw UserError("--eta", "must be >= 0", "the papers use 40");
  if (min_observations < 0) throw UserError("--min-observations", "must be >= 0");
}

void SolvePixels(const BasisView& basis, const PixelObservations& obs,
                 const PixelSolveOptions& options, PixelSolution* solution, int first_pixel) {
  options.Check(basis);
  const int k = options.components;
  const int min_obs = options.MinObservations();
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
#pragma omp parallel
  {
    RowMatrix qs(obs.views, k);
    Eigen::MatrixXd y(obs.views, 3);
    std::vector<float> row(k);

#pragma omp for schedule(dynamic, 64)
    for (int p = 0; p < obs.pixels; ++p) {
      int n = 0;
      for (int v = 0; v < obs.views; ++v) {
        const std::size_t i = obs.At(p, v);
        const float* rgb = &obs.rgb[3 * i];
        if (!(std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2]))) continue;
        BasisSample s;
        if (!SampleBasis(basis, obs.light[i].cast<double>(), obs.camera[i].cast<double>(), k,
                         options.lookup, row.data(), &s))
          continue;
        for (int c = 0; c < k; ++c) qs(n, c) = row[c];
        for (int ch = 0; ch < 3; ++ch) y(n, ch) = MapBrdf(rgb[ch], s.cos_weight, s.ref) - s.mean;
        ++n;
      }
      const std::size_t out = std::size_t(first_pixel) + p;
      solution->observations[out] = std::uint16_t(n);
      float* coeff = &solution->coefficients[out * 3 * k];
      if (n == 0) {
        solution->valid[out] = 0;
        solution->condition[out] = std::numeric_limits<float>::infinity();
        continue;
      }
      const auto q = qs.topRows(n);
      Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(k, k);
      normal.selfadjointView<Eigen::Lower>().rankUpdate(q.transpose());
      // The condition number needs only the eigenvalues (no vectors: several times cheaper);
      // the solve is a Cholesky factorisation of the ridge-regularised normal matrix.
      const Eigen::VectorXd ev =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(normal, Eigen::EigenvaluesOnly)
              .eigenvalues();
      const double condition = n < k || !(ev(0) > 0) ? std::numeric_limits<double>::infinity()
                                                     : std::sqrt(ev(k - 1) / ev(0));
      normal.diagonal().array() += options.eta;
      const Eigen::LLT<Eigen::MatrixXd> factor(normal);
      const Eigen::MatrixXd c = factor.solve(q.transpose() * y.topRows(n));
      double misfit = (q * c - y.topRows(n)).squaredNorm();
      bool finite = c.allFinite() && std::isfinite(misfit);
      for (int ch = 0; ch < 3; ++ch)
        for (int j = 0; j < k; ++j) coeff[ch * k + j] = finite ? float(c(j, ch)) : 0.0f;
      solution->condition[out] = float(condition);
      solution->residual[out] = finite ? float(std::sqrt(misfit / (3.0 * n))) : 0.0f;
      solution->valid[out] = finite && n >= min_obs && condition <= options.max_condition;
    }
  }
}

}  // namespace acq
