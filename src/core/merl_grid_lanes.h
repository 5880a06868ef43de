// merl::BinOf (merl_grid.cpp) in lanes (core/lanes.h): the flat bins of kLanes<T> observations'
// isotropic Rusinkiewicz angles at once, with the same edge slack, clamping and reciprocity
// fold (tests/test_merl_grid.cpp checks that both give the same bins).
#pragma once

#include "core/angles.h"
#include "core/lanes.h"
#include "core/merl_grid.h"

namespace acq::merl {

template <class T>
LaneMask<T> FlatBinOf(Lanes<T> theta_h, Lanes<T> theta_d, Lanes<T> phi_d) {
  using M = LaneMask<T>;
  const auto index = [](Lanes<T> x, int n) {  // IndexOf: truncated after the slack, clamped
    const M i = __builtin_convertvector(x + T(kEdgeSlack), M);
    return i < 0 ? M{} : (i > n - 1 ? M{} + (n - 1) : i);
  };
  const Lanes<T> zero{}, quarter = Splat<T>(T(kPi / 2));
  const M h = index(Sqrt<T>(Max<T>(theta_h, zero) / quarter) * T(kThetaH), kThetaH);
  const M d = index(Max<T>(theta_d, zero) / quarter * T(kThetaD), kThetaD);
  // Reciprocity: phi_d and phi_d + pi share a bin; a rounding-size negative phi_d is 0.
  const Lanes<T> phi = phi_d < T(-kEdgeSlack * kPi / kPhiD) ? phi_d + T(kPi) : phi_d;
  const M p = index(Max<T>(phi, zero) / T(kPi) * T(kPhiD), kPhiD);
  return p + kPhiD * (d + kThetaD * h);
}

}  // namespace acq::merl
