#include "brdf/pooled_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "brdf/log_mapping.h"
#include "brdf/pixel_rows.h"

namespace acq {
namespace {

constexpr int kCandidateGroups = 3;  // nearest in feature space, then judged by the data

// A ridge solve of rows q (n x k) against y (n x 3) with a factor of Q^T Q + lambda I, and its
// exact leave-one-view-out squared error.
struct RidgeFit {
  Eigen::MatrixXd c, r, w;
  Eigen::VectorXd h;
  double loo = 0;
  void Solve(const Eigen::LLT<Eigen::MatrixXd>& llt, const Eigen::Ref<const PixelRowMatrix>& q,
             const Eigen::MatrixXd& y) {
    c = llt.solve(q.transpose() * y);
    r = y - q * c;
    w = llt.matrixL().solve(q.transpose());  // k x n: h_v = |L^-1 q_v|^2
    h = w.colwise().squaredNorm().transpose();
    loo = (r.array().colwise() / (1.0 - h.array())).square().sum();
    if (!std::isfinite(loo)) loo = std::numeric_limits<double>::infinity();
  }
};

struct Centres {
  std::vector<Eigen::MatrixXd> coefficients;  // K x 3 per group
  explicit Centres(const PooledModel& model) {
    for (const PooledGroup& g : model.groups) {
      Eigen::MatrixXd c(model.components, 3);
      for (int ch = 0; ch < 3; ++ch)
        for (int j = 0; j < model.components; ++j) c(j, ch) = g.centre[ch * model.components + j];
      coefficients.push_back(c);
    }
  }
};

// One pixel at a time; buffers live as long as the worker thread.
struct PooledPixel {
  ViewRows rows;
  Factor factor;
  PixelRowMatrix q;
  Eigen::MatrixXd y, y_centre;
  RidgeFit alone, pooled;
  std::vector<float> coefficients;
  std::vector<double> feature;
  Eigen::MatrixXd candidate;

  void Solve(const BasisView& basis, const PixelObservations& obs, int p, const PooledModel& model,
             const Centres& centres, const PixelSolveOptions& options, PixelSolution* solution,
             std::size_t out, PriorChoice choice) {
    const int k = options.components, K = model.components;
    rows.Sample(basis, obs, p, K, options.lookup);
    q.resize(obs.views, K);
    y.resize(obs.views, 3);
    int n = 0;
    for (int v = 0; v < obs.views; ++v) {
      const float* rgb = &obs.rgb[3 * obs.At(p, v)];
      if (!(rows.ok[v] && std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2])))
        continue;
      const BasisSample& s = rows.samples[v];
      q.row(n) = rows.rows.row(v);
      for (int ch = 0; ch < 3; ++ch) y(n, ch) = MapBrdf(rgb[ch], s.cos_weight, s.ref) - s.mean;
      ++n;
    }
    float* coeff = &solution->coefficients[out * 3 * K];
    std::fill(coeff, coeff + 3 * K, 0.0f);
    solution->observations[out] = std::uint16_t(n);
    solution->group[out] = -1;
    if (n == 0) {
      solution->valid[out] = 0;
      solution->condition[out] = std::numeric_limits<float>::infinity();
      return;
    }
    const auto qn = q.topRows(n);
    const auto qk = qn.leftCols(k);
    const Eigen::MatrixXd yn = y.topRows(n);
    factor.Compute(qk, k, options.eta);  // the normal matrix with eta on its diagonal
    alone.Solve(factor.llt, qk, yn);
    coefficients.assign(3 * K, 0.0f);
    for (int ch = 0; ch < 3; ++ch)
      for (int j = 0; j < k; ++j) coefficients[ch * K + j] = float(alone.c(j, ch));

    double centre_misfit = 0;
    const int g = NearestGroup(model, centres, qn, yn, &centre_misfit);  // sets y_centre
    const Eigen::MatrixXd* residual = &alone.r;
    if (g >= 0) {
      const PooledGroup& group = model.groups[g];
      if (std::isinf(group.strength)) {  // the centre itself: nothing left to solve
        pooled.c.setZero(k, 3);
        pooled.r = y_centre;
        pooled.loo = y_centre.squaredNorm();
      } else {
        Eigen::MatrixXd m = factor.normal;
        m.diagonal().array() += group.strength - options.eta;
        pooled.Solve(Eigen::LLT<Eigen::MatrixXd>(m), qk, y_centre);
      }
      // The prior applies to a pixel its group's centre explains as well as it explains the
      // group's own pixels, and only where it predicts the left-out views better than the
      // pixel alone does.
      const bool of_group = centre_misfit <= group.misfit_limit;
      const bool better = choice == PriorChoice::kWhereExplained || pooled.loo <= alone.loo;
      if (of_group && better && pooled.c.allFinite()) {
        for (int ch = 0; ch < 3; ++ch)
          for (int j = 0; j < K; ++j)
            coefficients[ch * K + j] =
                float(centres.coefficients[g](j, ch) + (j < k ? pooled.c(j, ch) : 0.0));
        residual = &pooled.r;
        solution->group[out] = std::int16_t(g);
      }
      solution->departure[out] =
          float(model.Distance(coefficients.data(), K, group.centre.data(), K));
    }
    const double misfit = residual->squaredNorm();
    bool finite = std::isfinite(misfit);
    for (float c : coefficients) finite = finite && std::isfinite(c);
    if (finite) std::copy(coefficients.begin(), coefficients.end(), coeff);
    solution->condition[out] = float(factor.condition);
    solution->residual[out] = finite ? float(std::sqrt(misfit / (3.0 * n))) : 0.0f;
    // A pooled pixel's poorly constrained directions come from its group's centre: the
    // condition limit is the independent solve's, not its.
    solution->valid[out] = finite && n >= options.MinObservations() &&
                           (factor.condition <= options.max_condition || solution->group[out] >= 0);
    if (!finite) solution->departure[out] = 0;
  }

  // The group whose centre explains the observations best, among the kCandidateGroups nearest
  // to the pixel's independent solve in feature space; -1 without groups. Leaves the
  // observations less that centre's prediction in y_centre.
  int NearestGroup(const PooledModel& model, const Centres& centres,
                   const Eigen::Ref<const PixelRowMatrix>& qn, const Eigen::MatrixXd& yn,
                   double* rms_misfit) {
    const int groups = int(model.groups.size());
    if (groups == 0) return -1;
    feature.resize(3 * model.features);
    model.Feature(coefficients.data(), model.components, feature.data());
    const std::vector<int> near = model.NearestGroups(feature, kCandidateGroups);
    int best = near[0];
    double best_misfit = std::numeric_limits<double>::infinity();
    for (int g : near) {
      candidate = yn - qn * centres.coefficients[g];
      const double misfit = candidate.squaredNorm();
      if (misfit < best_misfit) best_misfit = misfit, best = g, y_centre.swap(candidate);
    }
    *rms_misfit = std::sqrt(best_misfit / (3.0 * double(yn.rows())));
    return best;
  }
};

}  // namespace

void SolvePixelsPooled(const BasisView& basis, const PixelObservations& obs,
                       const PooledModel& model, const PixelSolveOptions& options,
                       PixelSolution* solution, int first_pixel, PriorChoice choice) {
  options.Check(basis);
  const Centres centres(model);
#pragma omp parallel
  {
    PooledPixel one;
#pragma omp for schedule(dynamic, 16)
    for (int p = 0; p < obs.pixels; ++p) {
      if (p % 16 == 0) one.factor.estimator.Reset();  // warm starts within a chunk: see SolvePixels
      one.Solve(basis, obs, p, model, centres, options, solution, std::size_t(first_pixel) + p,
                choice);
    }
  }
}

}  // namespace acq
