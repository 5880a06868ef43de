// The one-pixel path's building blocks, shared by the independent solve (pixel_solver.cpp) and
// the pooled one (pooled_solver.cpp): the basis sampled at a pixel's directions in every view,
// and the factorisation of its rows with the condition estimate.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "brdf/basis_rows.h"
#include "brdf/pixel_solver.h"
#include "core/merl_grid_lanes.h"
#include "core/rusinkiewicz_lanes.h"

namespace acq {

using PixelRowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The basis at one pixel's directions in every view.
struct ViewRows {
  std::vector<std::uint8_t> ok;
  std::vector<BasisSample> samples;
  PixelRowMatrix rows;
  std::vector<float> row;  // one view's, before widening (kept: a pixel allocates nothing)
  void Sample(const BasisView& basis, const PixelObservations& obs, int pixel, int k,
              RowLookup lookup) {
    ok.assign(obs.views, 0);
    samples.resize(obs.views);
    rows.resize(obs.views, k);
    row.resize(k);
    for (int v = 0; v < obs.views; ++v) {
      const std::size_t i = obs.At(pixel, v);
      ok[v] = SampleBasis(basis, obs.light[i].cast<double>(), obs.camera[i].cast<double>(), k,
                          lookup, row.data(), &samples[v]);
      for (int c = 0; c < k; ++c) rows(v, c) = row[c];
    }
  }
  // The same with the directions converted kLanes<double> views at a time
  // (core/rusinkiewicz_lanes.h): for the normal search, which samples every candidate's views.
  // A bin may differ from Sample's where an angle lies within rounding of its edge.
  void SampleInLanes(const BasisView& basis, const PixelObservations& obs, int pixel, int k,
                     RowLookup lookup) {
    using V = Lanes<double>;
    constexpr int kWidth = kLanes<double>;
    ok.assign(obs.views, 0);
    samples.resize(obs.views);
    rows.setZero(obs.views, k);  // a view not sampled predicts nothing (callers skip it)
    row.resize(k);
    for (int first = 0; first < obs.views; first += kWidth) {
      const int count = std::min(kWidth, obs.views - first);
      V lx{}, ly{}, lz = Splat<double>(1), cx{}, cy{}, cz = Splat<double>(1);
      for (int l = 0; l < count; ++l) {
        const std::size_t i = obs.At(pixel, first + l);
        lx[l] = obs.light[i].x(), ly[l] = obs.light[i].y(), lz[l] = obs.light[i].z();
        cx[l] = obs.camera[i].x(), cy[l] = obs.camera[i].y(), cz[l] = obs.camera[i].z();
      }
      const IsotropicAnglesLanes<double> a = IsotropicAnglesOf<double>(lx, ly, lz, cx, cy, cz);
      const LaneMask<double> bins = lookup == RowLookup::kNearest
                                        ? merl::FlatBinOf<double>(a.theta_h, a.theta_d, a.phi_d)
                                        : LaneMask<double>{};
      for (int l = 0; l < count; ++l) {
        const int v = first + l;
        if (!(lz[l] > 0 && cz[l] > 0)) continue;  // SampleBasis's rule: both above the horizon
        if (lookup == RowLookup::kNearest) {  // SampleBasisAt's nearest bin, its row read in place
          const std::size_t bin = std::size_t(bins[l]);
          if (!(ok[v] = basis.valid[bin])) continue;
          const float* q = basis.Row(bin);
          for (int c = 0; c < k; ++c) rows(v, c) = q[c];
          samples[v] = {basis.mean[bin], basis.ref[bin], float(a.cos_weight[l])};
          continue;
        }
        RusinkiewiczAngles angles;
        angles.theta_h = a.theta_h[l], angles.theta_d = a.theta_d[l], angles.phi_d = a.phi_d[l];
        ok[v] = SampleBasisAt(basis, angles, a.cos_weight[l], k, lookup, row.data(), &samples[v]);
        for (int c = 0; c < k; ++c) rows(v, c) = row[c];
      }
    }
  }
};

// Factorisation of one set of sampled rows, reused while the set of views stays the same.
// Buffers live as long as the worker thread, so a pixel allocates nothing.
struct Factor {
  std::vector<std::uint8_t> views;  // which views the rows came from
  Eigen::LLT<Eigen::MatrixXd> llt, plain;
  Eigen::MatrixXd normal, gram;
  ConditionEstimator estimator;  // warm from the worker's previous pixel
  double condition = 0;
  void Compute(const Eigen::Ref<const PixelRowMatrix>& q, int k, double eta) {
    const int n = int(q.rows());
    normal.setZero(k, k);
    normal.selfadjointView<Eigen::Lower>().rankUpdate(q.transpose());
    // The condition number of the rows, sigma_max / sigma_min of the n x k matrix Q: from the
    // extreme eigenvalues of Q^T Q (k x k) or, with fewer rows than unknowns, of Q Q^T (n x n),
    // which has the same non-zero eigenvalues. With n < k the ridge settles the directions no
    // observation constrains (towards the mean BRDF) and this number says how much the fit to
    // the observations there are amplifies their noise. Infinite when the rows are dependent.
    // The solve is a Cholesky factorisation of the ridge-regularised normal matrix.
    const Eigen::MatrixXd* square = &normal;
    if (n < k) {
      gram.setZero(n, n);
      gram.selfadjointView<Eigen::Lower>().rankUpdate(q);
      square = &gram;
    }
    plain.compute(*square);
    condition = plain.info() != Eigen::Success ? std::numeric_limits<double>::infinity()
                                               : estimator.Estimate(*square, plain);
    if (!std::isfinite(condition) || condition <= 0)
      condition = std::numeric_limits<double>::infinity();
    normal.diagonal().array() += eta;
    llt.compute(normal);
  }
};

}  // namespace acq
