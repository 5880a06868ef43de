// The per-pixel solve of SolvePixels (rows per pixel) for kLanes<T> pixels at once, one pixel
// per SIMD lane (core/lanes.h): the Rusinkiewicz conversion, the log mapping, the normal matrix,
// both Cholesky factorisations, the condition estimate and the ridge solve of 8 pixels (double)
// or 16 (float) run as one stream of vector instructions. Eigen's dynamic-size routines, one
// pixel at a time, spent most of their time in loop and dispatch overhead on 20 x 20 matrices.
//
// Same algorithm and results as the one-pixel path in pixel_solver.cpp (tests/test_pixel_solver.cpp
// compares them), with one difference of layout: an unusable observation is a zero row (it adds
// nothing to the normal matrix, the right-hand side or the misfit) instead of a removed one.
// Pixels with fewer usable observations than unknowns are left to the one-pixel path, whose
// condition number then comes from Q Q^T.
#pragma once

#include <cstddef>
#include <vector>

#include "brdf/pixel_solver.h"
#include "core/lanes.h"

namespace acq {

template <class T>
class PixelBatch {
 public:
  static constexpr int kWidth = kLanes<T>;

  // Converts the observations of pixels [first, first + count), count <= kWidth, and samples
  // the basis rows at their directions.
  void Load(const BasisView& basis, const PixelObservations& observations, int first, int count,
            int k, RowLookup lookup);
  // A loaded pixel with fewer usable observations than k (or none): the caller solves it.
  bool Deferred(int lane) const { return used_[lane] < k_; }
  // Solves the other loaded pixels; pixel first + lane goes to solution index first_out + lane.
  void Solve(const PixelSolveOptions& options, PixelSolution* solution, std::size_t first_out);
  // The condition estimates of the next Solve start from scratch instead of from the previous
  // batch's eigenvectors (SolvePixels does this at every OpenMP chunk, for determinism).
  void ColdStart() { largest_.clear(); }

 private:
  using V = Lanes<T>;
  using M = LaneMask<T>;
  void Factorise(T eta, M* ok);  // factor_ = Cholesky of normal_ + eta I, lower, packed by rows
  // Columns x + c * stride, c < kColumns: x <- (L L^T)^-1 x with factor_ = L.
  template <int kColumns>
  void SolveFactor(V* x, std::size_t stride) const;
  void EstimateCondition(M skip, V* condition);
  // The ridge's hat value of each lane's row q (k values, stride 1): |L^-1 q|^2, L = factor_.
  V HatValue(const V* q);

  static constexpr int kBlock = 4;  // register blocks of the products: 4 x 4 lanes vectors
  int k_ = 0, stride_ = 0, views_ = 0, padded_views_ = 0, count_ = 0;
  int used_[kWidth] = {};
  std::vector<V> rows_;  // views x stride_: the basis rows, zero where the observation is unusable
  std::vector<V> y_;     // views x 3: the log-mapped observations less the mean, or zero
  std::vector<V> normal_;                  // k (k + 1) / 2: Q^T Q, lower triangle packed by rows
  std::vector<V> square_;                  // k x k: Q^T Q in full, for the power iteration
  std::vector<V> factor_;                  // the same shape as normal_: a Cholesky factor
  std::vector<V> inv_diag_;                // k: 1 / the factor's diagonal
  std::vector<V> largest_, smallest_, w_;  // k: warm starts of the condition estimate
  std::vector<V> rhs_;                     // 3 x k
  std::vector<V> z_;                       // k: scratch of HatValue
  std::vector<float> row_;                 // one sampled row
};

extern template class PixelBatch<double>;
extern template class PixelBatch<float>;

}  // namespace acq
