// splitmix64's finaliser (Steele, Lea and Flood 2014): a well-spread 64-bit key from any 64-bit
// value, for seeding and sampling that must not depend on the order things are done in. One
// place for its constants; callers add their own increment.
#pragma once

#include <cstdint>

namespace acq {

inline constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ull;  // 2^64 / golden ratio

inline std::uint64_t SplitMix64Finalise(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace acq
