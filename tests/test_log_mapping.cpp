#include <catch2/catch.hpp>
#include <random>

#include "brdf/log_mapping.h"

using namespace acq;

TEST_CASE("log mapping and its inverse", "[mapping]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> rho(0.0, 200.0), cosw(0.01, 1.0), ref(0.0, 5.0);
  for (int i = 0; i < 10000; ++i) {
    const double r = rho(rng), c = cosw(rng), f = ref(rng);
    const double y = MapBrdf(r, c, f);
    REQUIRE(UnmapBrdf(y, c, f) == Approx(r).epsilon(1e-9).margin(1e-12));
  }
}

TEST_CASE("log mapping, hand computed", "[mapping]") {
  // rho cosw equal to the reference maps to 0; eps = 0.001 keeps rho = 0 finite.
  CHECK(MapBrdf(2.0, 0.5, 1.0) == Approx(0.0).margin(1e-15));
  CHECK(MapBrdf(0.0, 0.5, 1.0) == Approx(std::log(0.001 / 1.001)));
  CHECK(MapBrdf(0.0, 1.0, 0.0) == Approx(0.0).margin(1e-15));
  CHECK(MapBrdf(10.0, 1.0, 0.999) == Approx(std::log(10.001 / 1.0)));
  // Negative values ("no data", a fit's undershoot) are taken as 0.
  CHECK(MapBrdf(-1.0, 0.5, 1.0) == MapBrdf(0.0, 0.5, 1.0));
}
