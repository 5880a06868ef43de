#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "core/lanes.h"

using namespace acq;

namespace {

// Worst relative difference of Log and Atan2 in lanes from std::log and std::atan2 over values
// spanning the ranges the per-pixel solve meets (BRDF ratios from 1e-13 to 1e13, directions in
// every quadrant, signed zeros).
template <class T>
void WorstErrors(double* log_error, double* atan2_error) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), exponent(-30, 30);
  *log_error = *atan2_error = 0;
  for (int it = 0; it < 20000; ++it) {
    Lanes<T> y, x, v;
    for (int l = 0; l < kLanes<T>; ++l)
      y[l] = T(u(rng)), x[l] = T(u(rng)), v[l] = T(std::exp(exponent(rng)));
    // Every fifth draw one lane takes a signed zero or an axis (NaN: the draw kept); over the
    // draws every case meets every lane, whatever the target's width (kLanes: 2 to 16).
    const double keep = std::numeric_limits<double>::quiet_NaN();
    const double cases[5][2] = {{0, keep}, {-0.0, -0.5}, {keep, -0.0}, {keep, 0}, {1, keep}};
    if (it % 5 == 0) {
      const int l = (it / 25) % kLanes<T>;
      const double* c = cases[(it / 5) % 5];
      if (!std::isnan(c[0])) y[l] = T(c[0]);
      if (!std::isnan(c[1])) x[l] = T(c[1]);
    }
    const Lanes<T> a = Atan2<T>(y, x), lg = Log<T>(v);
    for (int l = 0; l < kLanes<T>; ++l) {
      const double ra = std::atan2(double(y[l]), double(x[l])), rl = std::log(double(v[l]));
      REQUIRE(std::signbit(a[l]) == std::signbit(ra));
      *atan2_error = std::max(*atan2_error, std::abs(a[l] - ra) / std::max(std::abs(ra), 1e-30));
      *log_error = std::max(*log_error, std::abs(lg[l] - rl) / std::max(std::abs(rl), 1e-30));
    }
  }
}

}  // namespace

TEST_CASE("log and atan2 in lanes agree with the standard library", "[lanes]") {
  double log_error, atan2_error;
  WorstErrors<double>(&log_error, &atan2_error);
  WARN("float64 lanes: log " << log_error << ", atan2 " << atan2_error);
  // A few units in the last place (2.2e-16 each): a bin edge moves by as little, the log
  // mapping's value by less than the float32 storage of an observation.
  CHECK(log_error < 1e-15);
  CHECK(atan2_error < 1e-15);
  WorstErrors<float>(&log_error, &atan2_error);
  WARN("float32 lanes: log " << log_error << ", atan2 " << atan2_error);
  CHECK(log_error < 1e-6);  // a few units of float32's 6e-8
  CHECK(atan2_error < 1e-6);
}

TEST_CASE("lanes: square root, min, max and masks act lane by lane", "[lanes]") {
  Lanes<double> a, b;
  for (int l = 0; l < kLanes<double>; ++l) a[l] = l * l, b[l] = 10 - l;
  const Lanes<double> r = Sqrt<double>(a), lo = Min<double>(a, b), hi = Max<double>(a, b);
  for (int l = 0; l < kLanes<double>; ++l) {
    CHECK(r[l] == l);
    CHECK(lo[l] == std::min(double(l * l), double(10 - l)));
    CHECK(hi[l] == std::max(double(l * l), double(10 - l)));
  }
  // Only the last lane is over the first threshold: Any looks at every lane.
  const double last = double((kLanes<double> - 1) * (kLanes<double> - 1));
  CHECK(Any<double>(a > last - 0.5));
  CHECK_FALSE(Any<double>(a > last));
}
