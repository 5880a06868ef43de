#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <exception>
#include <sstream>

#include "brdf/basis.h"
#include "brdf/log_mapping.h"
#include "core/error.h"
#include "core/progress.h"

namespace acq {
namespace {

using FloatMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;  // column-major

// Bins are processed in blocks of this many columns: large enough for efficient matrix
// products, small enough that a block converted to double stays in cache (270 x 512 x 8 B).
constexpr Eigen::Index kBlock = 512;

double MedianInPlace(float* v, int n) {
  // numpy's median convention: mean of the two middle values when n is even.
  float* mid = v + n / 2;
  std::nth_element(v, mid, v + n);
  if (n % 2) return *mid;
  const float below = *std::max_element(v, mid);
  return 0.5 * (double(below) + double(*mid));
}

std::string Settings(const MaterialSplit& split, const BasisOptions& options) {
  std::ostringstream s;
  s << "format: acq-basis\n"
    << "grid: [" << merl::kThetaH << ", " << merl::kThetaD << ", " << merl::kPhiD << "]\n"
    << "bin_centres: midpoint  # theta_h ((i+0.5)/90)^2 pi/2, theta_d, phi_d (j+0.5) deg\n"
    << "mapping: ln((rho*cosw + eps)/(rho_ref + eps))\n"
    << "eps: " << kLogMappingEps << "\n"
    << "cos_weight_min: " << merl::kCosWeightMin << "\n"
    << "reference: per-bin median of cos-weighted training BRDFs (R, G, B separate)\n"
    << "components_scaled_by_singular_values: true\n"
    << "components: " << options.components << "\n"
    << "training:\n";
  for (const auto& m : split.training) s << "  - " << m.name << "\n";
  s << "held_out:" << (split.held_out.empty() ? " []" : "") << "\n";
  for (const auto& m : split.held_out) s << "  - " << m.name << "\n";
  return s.str();
}

}  // namespace

void BasisOptions::Check(int training_rows) const {
  if (components < 1) throw UserError("--components", "must be at least 1", "the default is 64");
  if (components > training_rows)
    throw UserError("--components",
                    std::to_string(components) +
                        " components asked, but the training set has only " +
                        std::to_string(training_rows) + " rows (3 per material)",
                    "use fewer components or more materials");
}

BasisView BasisData::View() const {
  return {components,  training_rows, valid.data(),    ref.data(),
          mean.data(), q.data(),      singular_values, settings};
}

BasisData BuildBasis(const MaterialSplit& split, const BasisOptions& options) {
  const int m = int(3 * split.training.size());
  options.Check(m);
  const merl::GridGeometry& grid = merl::Geometry();
  const Eigen::Index nv = Eigen::Index(grid.valid_bins.size());

  // 1. Tabulate every training channel at the valid bins, cos-weighted: X(row, valid bin).
  FloatMatrix x(m, nv);
  {
    Progress progress("basis: loading materials", split.training.size(), options.progress);
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic)
    for (int i = 0; i < int(split.training.size()); ++i) {
      try {
        const MerlBrdf brdf = LoadMaterial(split.training[i]);
        for (Eigen::Index v = 0; v < nv; ++v) {
          const std::uint32_t bin = grid.valid_bins[v];
          for (int c = 0; c < 3; ++c)
            x(3 * i + c, v) = float(std::max(brdf.Value(c, bin), 0.0) * grid.cos_weight[bin]);
        }
      } catch (...) {
#pragma omp critical
        if (!error) error = std::current_exception();
      }
      progress.Tick();
    }
    if (error) std::rethrow_exception(error);
  }

  BasisData basis;
  basis.components = options.components;
  basis.training_rows = m;
  basis.valid = grid.valid;
  basis.ref.assign(merl::kBins, 0.0f);
  basis.mean.assign(merl::kBins, 0.0f);

  // 2. Per bin: median reference, log mapping, mean; then accumulate the Gram matrix.
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(m, m);
  const Eigen::Index blocks = (nv + kBlock - 1) / kBlock;
  {
    Progress progress("basis: mapping and Gram matrix", std::size_t(blocks), options.progress);
#pragma omp parallel
    {
      Eigen::MatrixXd gram_local = Eigen::MatrixXd::Zero(m, m);
      std::vector<float> scratch(m);
#pragma omp for schedule(dynamic)
      for (Eigen::Index b = 0; b < blocks; ++b) {
        const Eigen::Index start = b * kBlock, n = std::min(kBlock, nv - start);
        for (Eigen::Index v = start; v < start + n; ++v) {
          float* column = &x(0, v);
          std::copy(column, column + m, scratch.begin());
          const double ref = MedianInPlace(scratch.data(), m);
          double sum = 0.0;
          for (int r = 0; r < m; ++r) {
            const double y = MapCosWeighted(column[r], ref);
            column[r] = float(y);
            sum += y;
          }
          const double mean = sum / m;
          for (int r = 0; r < m; ++r) column[r] = float(double(column[r]) - mean);
          const std::uint32_t bin = grid.valid_bins[v];
          basis.ref[bin] = float(ref);
          basis.mean[bin] = float(mean);
        }
        const Eigen::MatrixXd block = x.middleCols(start, n).cast<double>();
        gram_local.selfadjointView<Eigen::Lower>().rankUpdate(block);
        progress.Tick();
      }
#pragma omp critical
      gram += gram_local;
    }
  }

  // 3. PCA: Gram = V L V^T; singular values sqrt(L); scaled components Q = Xc^T V.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(gram.selfadjointView<Eigen::Lower>());
  const int k = options.components;
  Eigen::MatrixXd v_k(m, k);
  basis.singular_values.resize(m);
  for (int i = 0; i < m; ++i) {
    const int src = m - 1 - i;  // eigenvalues come ascending
    basis.singular_values[i] = std::sqrt(std::max(eig.eigenvalues()(src), 0.0));
    if (i < k) v_k.col(i) = eig.eigenvectors().col(src);
  }
  // Fix each component's arbitrary sign: the largest-magnitude loading is positive.
  for (int i = 0; i < k; ++i) {
    Eigen::Index arg;
    v_k.col(i).cwiseAbs().maxCoeff(&arg);
    if (v_k(arg, i) < 0) v_k.col(i) *= -1.0;
  }
  basis.q.assign(merl::kBins * std::size_t(k), 0.0f);
  {
    Progress progress("basis: components", std::size_t(blocks), options.progress);
#pragma omp parallel for schedule(dynamic)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index start = b * kBlock, n = std::min(kBlock, nv - start);
      const Eigen::MatrixXd rows = x.middleCols(start, n).cast<double>().transpose() * v_k;
      for (Eigen::Index v = 0; v < n; ++v) {
        float* out = basis.q.data() + std::size_t(grid.valid_bins[start + v]) * k;
        for (int c = 0; c < k; ++c) out[c] = float(rows(v, c));
      }
      progress.Tick();
    }
  }
  basis.settings = Settings(split, options);
  return basis;
}

}  // namespace acq
