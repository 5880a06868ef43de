// SIMD lanes for kernels that do the same small computation for many pixels at once: one value
// per lane in a GCC/Clang vector as wide as the target's widest register (kLaneBytes: 64 bytes,
// 8 doubles or 16 floats, with AVX-512; 32 with AVX; 16 without). Arithmetic, compares
// and `mask ? a : b` work lane by lane; the functions here are the few the kernels need that the
// vector types lack, written as plain arithmetic so they compile to vector instructions.
//
// Accuracy: Log and Atan2 agree with std::log and std::atan2 to a few units in the last place
// (tests/test_lanes.cpp); a bin index computed from them matches the scalar one except where
// an angle is within rounding of a bin edge.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace acq {

// Vectors wider than the target's registers are split by GCC's generic lowering, which on AVX2
// scalarised the selects and spilled every half through the stack: 64-byte lanes on an AVX2
// machine spent 4x as long in Atan2, and the normal search on a 256 x 256 card took 8.0 s
// against 5.7-6.4 s with 32-byte lanes (docs/reconstruction.md, "Search methods and time").
// Results do not depend on the width: each lane is its own pixel or view.
#if defined(__AVX512F__)
inline constexpr int kLaneBytes = 64;
#elif defined(__AVX__)
inline constexpr int kLaneBytes = 32;
#else
inline constexpr int kLaneBytes = 16;
#endif

template <class T>
struct LaneTraits;
template <>
struct LaneTraits<double> {
  typedef double Value __attribute__((vector_size(kLaneBytes)));
  typedef std::int64_t Mask __attribute__((vector_size(kLaneBytes)));
  using Bits = std::uint64_t;
};
template <>
struct LaneTraits<float> {
  typedef float Value __attribute__((vector_size(kLaneBytes)));
  typedef std::int32_t Mask __attribute__((vector_size(kLaneBytes)));
  using Bits = std::uint32_t;
};

template <class T>
using Lanes = typename LaneTraits<T>::Value;
template <class T>
using LaneMask = typename LaneTraits<T>::Mask;  // -1 where true, 0 where false
template <class T>
constexpr int kLanes = int(kLaneBytes / sizeof(T));

template <class T>
Lanes<T> Splat(T x) {
  return Lanes<T>{} + x;
}

template <class T>
Lanes<T> Sqrt(Lanes<T> x) {
  // A plain loop: with -fno-math-errno (meson.build) GCC emits one vector square root.
  for (int i = 0; i < kLanes<T>; ++i) x[i] = std::sqrt(x[i]);
  return x;
}

template <class T>
Lanes<T> Abs(Lanes<T> x) {
  return x < T(0) ? -x : x;
}

template <class T>
Lanes<T> Min(Lanes<T> a, Lanes<T> b) {
  return a < b ? a : b;
}
template <class T>
Lanes<T> Max(Lanes<T> a, Lanes<T> b) {
  return a > b ? a : b;
}

template <class T>
bool Any(LaneMask<T> m) {
  for (int i = 0; i < kLanes<T>; ++i)
    if (m[i]) return true;
  return false;
}

// atan(t) for t in [0, 1]: Cephes' rational approximation, with t > 0.66 first reduced to
// (t - 1) / (t + 1) around pi/4 as Cephes does.
template <class T>
Lanes<T> AtanUnit(Lanes<T> t) {
  const auto big = t > T(0.66);
  const Lanes<T> x = big ? (t - T(1)) / (t + T(1)) : t;
  const Lanes<T> z = x * x;
  const Lanes<T> p = (((T(-8.750608600031904122785e-1) * z + T(-1.615753718733365076637e1)) * z +
                       T(-7.500855792314704667340e1)) *
                          z +
                      T(-1.228866684490136173410e2)) *
                         z +
                     T(-6.485021904942025371773e1);
  const Lanes<T> q = ((((z + T(2.485846490142306297962e1)) * z + T(1.650270098316988542046e2)) * z +
                       T(4.328810604912902668951e2)) *
                          z +
                      T(4.853903996359136964868e2)) *
                         z +
                     T(1.945506571482613964425e2);
  const Lanes<T> r = x + x * (z * p / q);
  return big ? r + T(0.78539816339744830962) : r;
}

// Where the sign bit is set (negative values and -0).
template <class T>
LaneMask<T> SignBit(Lanes<T> x) {
  LaneMask<T> bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits < 0;
}

// atan2(y, x) lane by lane, with std::atan2's signs: y = -0 gives -0 or -pi, as the scalar
// conversion's bins expect.
template <class T>
Lanes<T> Atan2(Lanes<T> y, Lanes<T> x) {
  const Lanes<T> ay = Abs<T>(y), ax = Abs<T>(x);
  const Lanes<T> lo = Min<T>(ay, ax), hi = Max<T>(ay, ax);
  const Lanes<T> t = hi > T(0) ? lo / hi : Splat<T>(0);
  Lanes<T> r = AtanUnit<T>(t);
  r = ay > ax ? T(1.57079632679489661923) - r : r;
  r = SignBit<T>(x) ? T(3.14159265358979323846) - r : r;
  return SignBit<T>(y) ? -r : r;
}

// Natural logarithm of positive, finite, normal values: x = m 2^e with m in [sqrt(1/2),
// sqrt(2)), log(m) = 2 atanh(s) with s = (m - 1) / (m + 1), |s| < 0.172, as an odd series.
template <class T>
Lanes<T> Log(Lanes<T> x) {
  using Bits = typename LaneTraits<T>::Bits;
  using Int = std::make_signed_t<Bits>;
  constexpr int kMantissa = sizeof(T) == 8 ? 52 : 23;
  constexpr Bits kExponentMask = sizeof(T) == 8 ? 0x7ffULL : 0xffU;
  constexpr Int kBias = sizeof(T) == 8 ? 1023 : 127;
  constexpr Bits kOne = Bits(kBias) << kMantissa;
  constexpr Bits kMantissaMask = (Bits(1) << kMantissa) - 1;
  typedef Bits BitLanes __attribute__((vector_size(kLaneBytes)));
  BitLanes bits;
  std::memcpy(&bits, &x, sizeof bits);
  LaneMask<T> e = LaneMask<T>((bits >> kMantissa) & kExponentMask) - kBias;
  bits = (bits & kMantissaMask) | kOne;
  Lanes<T> m;
  std::memcpy(&m, &bits, sizeof m);  // in [1, 2)
  const auto high = m > T(1.41421356237309504880);
  m = high ? m * T(0.5) : m;
  e = high ? e + 1 : e;
  const Lanes<T> s = (m - T(1)) / (m + T(1)), z = s * s;
  // 2 atanh(s) = 2 (s + s^3/3 + s^5/5 + ...); z < 0.0295, so eleven terms reach 1e-17 (double),
  // five reach 1e-9 (float).
  Lanes<T> series;
  if constexpr (sizeof(T) == 8) {
    series = Splat<T>(T(1.0 / 21));
    for (int i = 19; i >= 1; i -= 2) series = series * z + T(1.0 / i);
  } else {
    series = Splat<T>(T(1.0 / 9));
    for (int i = 7; i >= 1; i -= 2) series = series * z + T(1.0 / i);
  }
  const Lanes<T> exponent = __builtin_convertvector(e, Lanes<T>);
  return T(2) * s * series + exponent * T(0.69314718055994530942);
}

}  // namespace acq
