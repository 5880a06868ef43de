#include "brdf/pixel_batch.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "brdf/log_mapping.h"
#include "core/merl_grid_lanes.h"
#include "core/rusinkiewicz_lanes.h"

namespace acq {
namespace {

constexpr std::size_t Packed(int i, int j) {  // (i, j), j <= i, of a lower triangle by rows
  return std::size_t(i) * (i + 1) / 2 + j;
}

// sum_m a[m] b[m], m < n, for kColumns vectors b_c = b + c * stride at once, in four partial
// sums each: a single running sum would make every multiply-add wait for the previous one
// (four cycles of latency), which is what bounded the factorisations and solves.
template <int kColumns, class V>
[[gnu::always_inline]] inline void Dots(const V* a, const V* b, std::size_t stride, int n, V* out) {
  V acc[kColumns][4] = {};
  int m = 0;
  for (; m + 4 <= n; m += 4)
    for (int c = 0; c < kColumns; ++c)
      for (int u = 0; u < 4; ++u) acc[c][u] += a[m + u] * b[c * stride + m + u];
  for (; m < n; ++m)
    for (int c = 0; c < kColumns; ++c) acc[c][0] += a[m] * b[c * stride + m];
  for (int c = 0; c < kColumns; ++c) out[c] = (acc[c][0] + acc[c][1]) + (acc[c][2] + acc[c][3]);
}

}  // namespace

// The conversion is IsotropicAnglesFromDirections (core/rusinkiewicz.cpp) in lanes, step for
// step, so both paths put an observation in the same bin.
template <class T>
void PixelBatch<T>::Load(const BasisView& basis, const PixelObservations& obs, int first, int count,
                         int k, RowLookup lookup) {
  k_ = k;
  views_ = obs.views;
  count_ = count;
  // Padded with zero columns and rows for the blocked loops.
  stride_ = (k + kBlock - 1) / kBlock * kBlock;
  padded_views_ = (views_ + kBlock - 1) / kBlock * kBlock;
  rows_.assign(std::size_t(padded_views_) * stride_, V{});
  y_.assign(std::size_t(padded_views_) * 3, V{});
  row_.resize(k);
  std::fill(std::begin(used_), std::end(used_), 0);
  for (int v = 0; v < views_; ++v) {
    // Lanes past `count` see straight down and no value: they take no part.
    V lx{}, ly{}, lz = Splat<T>(1), cx{}, cy{}, cz = Splat<T>(1);
    const V no_value = Splat<T>(std::numeric_limits<T>::quiet_NaN());
    V rgb[3] = {no_value, no_value, no_value};
    for (int l = 0; l < count; ++l) {
      const std::size_t i = obs.At(first + l, v);
      lx[l] = obs.light[i].x(), ly[l] = obs.light[i].y(), lz[l] = obs.light[i].z();
      cx[l] = obs.camera[i].x(), cy[l] = obs.camera[i].y(), cz[l] = obs.camera[i].z();
      for (int ch = 0; ch < 3; ++ch) rgb[ch][l] = obs.rgb[3 * i + ch];
    }
    const IsotropicAnglesLanes<T> angles = IsotropicAnglesOf<T>(lx, ly, lz, cx, cy, cz);
    const V &theta_h = angles.theta_h, &theta_d = angles.theta_d, &phi_d = angles.phi_d;
    const V& cos_weight = angles.cos_weight;

    // Nearest bins in lanes; interpolated rows one observation at a time (SampleBasisAt).
    const M bins =
        lookup == RowLookup::kNearest ? merl::FlatBinOf<T>(theta_h, theta_d, phi_d) : M{};
    V mean{}, ref{};
    M used{};
    for (int l = 0; l < count; ++l) {
      if (!(lz[l] > 0 && cz[l] > 0)) continue;
      if (!(std::isfinite(rgb[0][l]) && std::isfinite(rgb[1][l]) && std::isfinite(rgb[2][l])))
        continue;
      const float* q = row_.data();
      if (lookup == RowLookup::kNearest) {
        const std::size_t bin = std::size_t(bins[l]);
        if (!basis.valid[bin]) continue;
        q = basis.Row(bin);
        mean[l] = basis.mean[bin], ref[l] = basis.ref[bin];
      } else {
        RusinkiewiczAngles a;
        a.theta_h = theta_h[l], a.theta_d = theta_d[l], a.phi_d = phi_d[l];
        BasisSample s;
        if (!SampleBasisAt(basis, a, cos_weight[l], k, lookup, row_.data(), &s)) continue;
        mean[l] = s.mean, ref[l] = s.ref;
      }
      V* r = &rows_[std::size_t(v) * stride_];
      for (int c = 0; c < k; ++c) r[c][l] = q[c];
      used[l] = -1;
      ++used_[l];
    }
    // MapBrdf (log_mapping.h) in lanes.
    const T eps = T(kLogMappingEps);
    for (int ch = 0; ch < 3; ++ch) {
      const V mapped =
          Log<T>((Max<T>(rgb[ch], Splat<T>(0)) * cos_weight + eps) / (ref + eps)) - mean;
      y_[std::size_t(v) * 3 + ch] = used ? mapped : Splat<T>(0);
    }
  }
}

template <class T>
void PixelBatch<T>::Factorise(T eta, M* ok) {
  const int k = k_;
  factor_.resize(normal_.size());
  inv_diag_.resize(k);
  *ok = ~M{};
  for (int i = 0; i < k; ++i) {
    const V* li = &factor_[Packed(i, 0)];
    for (int j = 0; j <= i; ++j) {
      V dot;
      Dots<1>(li, &factor_[Packed(j, 0)], 0, j, &dot);
      V s = normal_[Packed(i, j)] - dot;
      if (i == j) {
        s += eta;
        *ok &= s > T(0);
        const V d = Sqrt<T>(Max<T>(s, Splat<T>(std::numeric_limits<T>::min())));
        factor_[Packed(i, i)] = d;
        inv_diag_[i] = T(1) / d;
      } else {
        factor_[Packed(i, j)] = s * inv_diag_[j];
      }
    }
  }
}

// Columns x_c = x + c * stride, solved together so each element of the factor is loaded once
// for all of them.
template <class T>
template <int kColumns>
void PixelBatch<T>::SolveFactor(V* x, std::size_t stride) const {
  const int k = k_;
  for (int i = 0; i < k; ++i) {  // L z = x
    const V* li = &factor_[Packed(i, 0)];
    V dot[kColumns];
    Dots<kColumns>(li, x, stride, i, dot);
    for (int c = 0; c < kColumns; ++c)
      x[c * stride + i] = (x[c * stride + i] - dot[c]) * inv_diag_[i];
  }
  for (int i = k - 1; i >= 0; --i) {  // L^T x = z, a column of L^T being a row of L
    const V* li = &factor_[Packed(i, 0)];
    V xi[kColumns];
    for (int c = 0; c < kColumns; ++c) xi[c] = x[c * stride + i] *= inv_diag_[i];
    for (int m = 0; m < i; ++m)
      for (int c = 0; c < kColumns; ++c) x[c * stride + m] -= li[m] * xi[c];
  }
}

template <class T>
typename PixelBatch<T>::V PixelBatch<T>::HatValue(const V* q) {
  z_.resize(k_);
  V h{};
  for (int i = 0; i < k_; ++i) {  // L z = q, as SolveFactor's first half
    V dot;
    Dots<1>(&factor_[Packed(i, 0)], z_.data(), 0, i, &dot);
    z_[i] = (q[i] - dot) * inv_diag_[i];
    h += z_[i] * z_[i];
  }
  return h;
}

// ConditionEstimator::Estimate (pixel_solver.cpp) in lanes: power iteration on Q^T Q and inverse
// iteration on its Cholesky factor, each lane stopping when its own Rayleigh quotient settles.
// Lanes in `skip` (no factor, or not loaded) are settled from the start.
template <class T>
void PixelBatch<T>::EstimateCondition(M skip, V* condition) {
  constexpr int kMaxSteps = ConditionIteration::kMaxSteps;
  const T settled_tolerance = T(ConditionIteration::kSettled);
  const int k = k_;
  const T cold = T(1 / std::sqrt(double(k)));
  if (int(largest_.size()) != k) {
    largest_.assign(k, Splat<T>(cold));
    smallest_ = largest_;
  }
  w_.resize(k);
  // The normal matrix in full for the power iteration's products, row by row.
  square_.resize(std::size_t(k) * k);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j <= i; ++j)
      square_[std::size_t(i) * k + j] = square_[std::size_t(j) * k + i] = normal_[Packed(i, j)];
  V quotient[2];
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<V>& x = pass == 0 ? largest_ : smallest_;
    M done = skip;
    V q_prev{};
    for (int step = 0; step < kMaxSteps && Any<T>(~done); ++step) {
      if (pass == 0) {  // w = A x
        for (int i = 0; i < k; ++i) Dots<1>(&square_[std::size_t(i) * k], x.data(), 0, k, &w_[i]);
      } else {  // w = A^-1 x
        std::copy(x.begin(), x.end(), w_.begin());
        SolveFactor<1>(w_.data(), 0);
      }
      V q, norm2;
      Dots<1>(x.data(), w_.data(), 0, k, &q);
      Dots<1>(w_.data(), w_.data(), 0, k, &norm2);
      const V inv_norm = T(1) / Sqrt<T>(norm2);
      for (int i = 0; i < k; ++i) x[i] = done ? x[i] : w_[i] * inv_norm;
      const M settled = step > 0 ? Abs<T>(q - q_prev) <= settled_tolerance * q : M{};
      q_prev = done ? q_prev : q;
      done |= settled;
    }
    quotient[pass] = q_prev;
  }
  const V largest = quotient[0], inverse = quotient[1];
  const T inf = std::numeric_limits<T>::infinity();
  const M good = ~skip & (largest > T(0)) & (inverse > T(0)) & (largest < inf) & (inverse < inf);
  *condition = good ? Sqrt<T>(largest * inverse) : Splat<T>(inf);
  // A lane without an estimate starts cold next time, as the one-pixel estimator does.
  for (int i = 0; i < k; ++i) {
    largest_[i] = good ? largest_[i] : Splat<T>(cold);
    smallest_[i] = good ? smallest_[i] : Splat<T>(cold);
  }
}

template <class T>
void PixelBatch<T>::Solve(const PixelSolveOptions& options, PixelSolution* solution,
                          std::size_t first_out) {
  const int k = k_, kp = stride_, n = padded_views_;
  M solved{};  // loaded lanes with enough observations
  for (int l = 0; l < count_; ++l) solved[l] = Deferred(l) ? 0 : -1;
  if (!Any<T>(solved)) return;
  // Q^T Q, lower triangle, in 4 x 4 blocks of accumulators held in registers: two loads a
  // multiply-add would leave the loop waiting on memory instead of arithmetic.
  normal_.resize(Packed(k, 0));
  for (int i0 = 0; i0 < kp; i0 += kBlock)
    for (int j0 = 0; j0 <= i0; j0 += kBlock) {
      V acc[kBlock][kBlock] = {};
      for (int v = 0; v < n; ++v) {
        const V* q = &rows_[std::size_t(v) * kp];
        for (int a = 0; a < kBlock; ++a)
          for (int b = 0; b < kBlock; ++b) acc[a][b] += q[i0 + a] * q[j0 + b];
      }
      for (int a = 0; a < kBlock && i0 + a < k; ++a)
        for (int b = 0; b < kBlock && j0 + b <= i0 + a; ++b)
          normal_[Packed(i0 + a, j0 + b)] = acc[a][b];
    }
  M plain_ok;
  Factorise(T(0), &plain_ok);
  V condition;
  EstimateCondition(~(solved & plain_ok), &condition);
  M ridge_ok;
  Factorise(T(options.eta), &ridge_ok);
  // Right-hand sides Q^T y (blocks of 4 components x 3 channels), then the solves.
  rhs_.resize(std::size_t(3) * k);
  for (int c0 = 0; c0 < kp; c0 += kBlock) {
    V acc[kBlock][3] = {};
    for (int v = 0; v < n; ++v) {
      const V* q = &rows_[std::size_t(v) * kp + c0];
      const V* y = &y_[std::size_t(v) * 3];
      for (int a = 0; a < kBlock; ++a)
        for (int ch = 0; ch < 3; ++ch) acc[a][ch] += q[a] * y[ch];
    }
    for (int a = 0; a < kBlock && c0 + a < k; ++a)
      for (int ch = 0; ch < 3; ++ch) rhs_[std::size_t(ch) * k + c0 + a] = acc[a][ch];
  }
  SolveFactor<3>(rhs_.data(), std::size_t(k));
  // The misfit at the observations, 4 views at a time (zero rows add nothing).
  V misfit{};
  for (int v0 = 0; v0 < n; v0 += kBlock) {
    V fit[kBlock][3] = {};
    for (int c = 0; c < k; ++c) {
      const V coef[3] = {rhs_[c], rhs_[std::size_t(k) + c], rhs_[std::size_t(2) * k + c]};
      for (int a = 0; a < kBlock; ++a) {
        const V q = rows_[std::size_t(v0 + a) * kp + c];
        for (int ch = 0; ch < 3; ++ch) fit[a][ch] += q * coef[ch];
      }
    }
    for (int a = 0; a < kBlock; ++a) {
      V scale = Splat<T>(T(1));  // ResidualKind::kFit
      if (options.residual == ResidualKind::kLeaveOneViewOut && v0 + a < n) {
        // A zero row (unusable) has h = 0 and a zero error: it still adds nothing.
        const V h = HatValue(&rows_[std::size_t(v0 + a) * kp]);
        scale = T(1) / Max<T>(T(1) - h, Splat<T>(T(1e-12)));
      }
      for (int ch = 0; ch < 3; ++ch) {
        const V e = (fit[a][ch] - y_[std::size_t(v0 + a) * 3 + ch]) * scale;
        misfit += e * e;
      }
    }
  }
  for (int l = 0; l < count_; ++l) {
    if (!solved[l]) continue;
    const std::size_t out = first_out + l;
    bool finite = ridge_ok[l] && std::isfinite(misfit[l]);
    for (int i = 0; i < 3 * k && finite; ++i) finite = std::isfinite(rhs_[i][l]);
    float* coeff = &solution->coefficients[out * 3 * k];
    for (int i = 0; i < 3 * k; ++i) coeff[i] = finite ? float(rhs_[i][l]) : 0.0f;
    const double cond = condition[l];  // infinite where the plain factorisation failed
    solution->observations[out] = std::uint16_t(used_[l]);
    solution->condition[out] = float(cond);
    solution->residual[out] = finite ? float(std::sqrt(misfit[l] / (3.0 * used_[l]))) : 0.0f;
    solution->valid[out] =
        finite && used_[l] >= options.MinObservations() && cond <= options.max_condition;
  }
}

template class PixelBatch<double>;
template class PixelBatch<float>;

}  // namespace acq
