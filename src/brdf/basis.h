// The data-driven BRDF basis (NJR15; docs/architecture.md "The method in one page"): over the bins
// of the MERL grid, a horizon mask, the per-bin reference rho_ref (median of the cos-weighted
// training BRDFs), the mean mu of the log-mapped training set, and the principal components
// Q stored SCALED BY THEIR SINGULAR VALUES (Q = U S, so Xc^T = Q V^T); the ridge strength
// eta = 40 of the papers is only meaningful with this scaling.
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

// The ridge solve's defaults, in one place: the papers' k = 20 and eta = 40 (eta meaningful with
// the components scaled as above). Cross-validated over held-out materials, a smaller eta does
// better (docs/basis-generalisation.md, "Model order"); the default changes with the figures
// measured at it.
inline constexpr int kDefaultComponents = 20;
inline constexpr double kDefaultEta = 40.0;

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
