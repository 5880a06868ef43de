// Neural-BRDF fits (Sztrajman et al. 2021): a 6-21-21-3 multilayer perceptron per material,
// stored as a Keras weights file (HDF5). See data/nbrdf/README.md for the layout.
//
// Input x = [sin th_h, 0, cos th_h, d_x, d_y, d_z] (the half vector at phi_h = 0, then the
// difference vector in the half-vector frame); layers y = x W + b with ReLU after the first
// two; output RGB = exp(y) - 1, in MERL's units after MERL's channel scales.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>

#include "brdf/merl_brdf.h"
#include "core/rusinkiewicz.h"

namespace acq {

class NeuralBrdf {
 public:
  static constexpr int kInputs = 6, kHidden = 21, kOutputs = 3;
  using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  // Throws UserError naming the file and the dataset when the file is not such a fit.
  static NeuralBrdf Load(const std::string& path);

  static std::array<float, kInputs> Input(const RusinkiewiczAngles& a);

  // One evaluation; RGB in 1/sr. phi_d < 0 is folded to phi_d + pi (reciprocity), the domain
  // the fits were trained on. Below-horizon configurations are not meaningful.
  std::array<double, 3> Evaluate(const RusinkiewiczAngles& a) const;

  // Batch evaluation: inputs (B x 6) -> outputs (B x 3), RGB in 1/sr.
  RowMatrix EvaluateBatch(const RowMatrix& inputs) const;

  // The whole MERL grid at the bin centres. Masked bins are -1 ("no data"); outputs below
  // zero (exp(y) < 1, a fit's undershoot) are clamped to 0.
  MerlBrdf Tabulate() const;

 private:
  RowMatrix w1_, w2_, w3_;  // (6 x 21), (21 x 21), (21 x 3)
  Eigen::RowVectorXf b1_, b2_, b3_;
};

}  // namespace acq
