// The data-driven BRDF basis (NJR15; docs/architecture.md "The method in one page"): over the bins
// of the MERL grid, a horizon mask, the per-bin reference rho_ref (median of the cos-weighted
// training BRDFs), the mean mu of the log-mapped training set, and the principal components
// Q stored SCALED BY THEIR SINGULAR VALUES (Q = U S, so Xc^T = Q V^T); the ridge strength
// eta (the papers' 40, our kDefaultEta) is only meaningful with this scaling.
//
// BasisView is what every consumer reads; it is backed either by BasisData (built in memory)
// or by a memory-mapped basis file (basis_file.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "brdf/materials.h"
#include "core/merl_grid.h"

namespace acq {

// The ridge solve's defaults, in one place (eta meaningful with the components scaled as above).
// k = 20 as in the papers: from 10 to 30 it hardly matters at 20 directions. eta = 20, not the
// papers' 40: chosen by 5-fold cross-validation over the 126 MERL and RGL materials with the
// directions optimised for each fold's basis (docs/basis-generalisation.md), where eta = 20
// beats 40 on both sources (RGL 0.268 against 0.291, MERL 0.174 against 0.187) and ties 10 on
// the medians (0.269, 0.172) with a better worst material (0.98 against 1.26) and a lower
// noise gain (0.73 against 0.88).
inline constexpr int kDefaultComponents = 20;
inline constexpr double kDefaultEta = 20.0;

struct BasisView {
  int components = 0;                       // k stored
  int training_rows = 0;                    // m: 3 x number of training materials
  const std::uint8_t* valid = nullptr;      // kBins
  const float* ref = nullptr;               // kBins, rho_ref (cos-weighted), 0 where invalid
  const float* mean = nullptr;              // kBins, mu, 0 where invalid
  const float* q = nullptr;                 // kBins x components, row-major (one row per bin)
  std::span<const double> singular_values;  // all of them, descending (training_rows)
  std::string_view settings;                // YAML text: how it was built

  const float* Row(std::size_t bin) const { return q + bin * std::size_t(components); }
};

struct BasisOptions {
  int components = 64;  // k stored; reconstructions may use any k up to this
  bool progress = true;
  void Check(int training_rows) const;  // throws UserError
};

struct BasisData {
  int components = 0, training_rows = 0;
  std::vector<std::uint8_t> valid;
  std::vector<float> ref, mean, q;
  std::vector<double> singular_values;
  std::string settings;
  BasisView View() const;
};

// Streams the training set through float storage (3 x materials x valid bins x 4 bytes) and
// accumulates the Gram matrix Xc Xc^T in double, block by block; never holds the matrix in
// double. PCA from the Gram matrix's eigendecomposition.
BasisData BuildBasis(const MaterialSplit& split, const BasisOptions& options);

}  // namespace acq
