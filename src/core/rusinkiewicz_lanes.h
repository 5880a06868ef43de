// IsotropicAnglesFromDirections (rusinkiewicz.cpp) and merl::CosWeight in lanes
// (core/lanes.h): the half/difference angles of kLanes<T> direction pairs at once, for the
// kernels that convert every observation (the batched per-pixel solve, the normal search).
// Same formulas as the scalar conversion; its atan2s agree to a few units in the last place.
#pragma once

#include "core/lanes.h"
#include "core/merl_grid.h"

namespace acq {

template <class T>
struct IsotropicAnglesLanes {
  Lanes<T> theta_h, theta_d, phi_d;
  Lanes<T> cos_weight;  // merl::CosWeight: l.z c.z clamped to [kCosWeightMin, 1]
};

// Light (lx, ly, lz) and camera (cx, cy, cz) directions, unit, lane by lane.
template <class T>
IsotropicAnglesLanes<T> IsotropicAnglesOf(Lanes<T> lx, Lanes<T> ly, Lanes<T> lz, Lanes<T> cx,
                                          Lanes<T> cy, Lanes<T> cz) {
  using V = Lanes<T>;
  using M = LaneMask<T>;
  V hx = lx + cx, hy = ly + cy, hz = lz + cz;
  const V inv_norm = T(1) / Sqrt<T>(hx * hx + hy * hy + hz * hz);
  hx *= inv_norm, hy *= inv_norm, hz *= inv_norm;
  const V sin_h = Sqrt<T>(hx * hx + hy * hy), cos_h = hz;
  IsotropicAnglesLanes<T> a;
  a.theta_h = Atan2<T>(sin_h, cos_h);
  const M pole = sin_h < T(1e-12);
  const V cos_p = pole ? Splat<T>(1) : hx / sin_h, sin_p = pole ? Splat<T>(0) : hy / sin_h;
  const V x1 = cos_p * lx + sin_p * ly, y1 = -sin_p * lx + cos_p * ly;
  const V dx = cos_h * x1 - sin_h * lz, dz = sin_h * x1 + cos_h * lz;
  a.theta_d = Atan2<T>(Sqrt<T>(dx * dx + y1 * y1), dz);
  a.phi_d = Atan2<T>(y1, dx);
  a.cos_weight = Min<T>(Max<T>(lz * cz, Splat<T>(T(merl::kCosWeightMin))), Splat<T>(1));
  return a;
}

}  // namespace acq
