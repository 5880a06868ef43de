#include <catch2/catch.hpp>

#include <fstream>

#include "brdf/neural_brdf.h"
#include "core/angles.h"
#include "test_helpers.h"

using namespace acq;

TEST_CASE("neural-BRDF evaluation matches an independent numpy evaluation", "[nbrdf]") {
  // From tools/nbrdf_reference_values.py data/nbrdf/merl/alum-bronze.h5 (float64 numpy,
  // following data/nbrdf/README.md). We evaluate in float32 as Keras does: 1e-5 relative
  // covers float32 rounding through three layers and exp, and nothing else.
  struct Expected {
    double th, td, pd, r, g, b;
  };
  const Expected expected[] = {
      {0, 0, 0, 3.22088874, 1.33949059, 0.506085278},
      {10, 30, 45, 0.0815408301, 0.0633430364, 0.0436539528},
      {45, 60, 170, 0.0137917129, 0.0109273792, 0.00736896154},
      {2.5, 80, 90, 30.1188111, 21.8327202, 19.4292831},
  };
  const NeuralBrdf brdf = NeuralBrdf::Load(test::DataPath("nbrdf/merl/alum-bronze.h5"));
  for (const Expected& e : expected) {
    RusinkiewiczAngles a;
    a.theta_h = DegToRad(e.th);
    a.theta_d = DegToRad(e.td);
    a.phi_d = DegToRad(e.pd);
    const auto rgb = brdf.Evaluate(a);
    INFO("theta_h " << e.th << " theta_d " << e.td << " phi_d " << e.pd);
    CHECK(rgb[0] == Approx(e.r).epsilon(1e-5));
    CHECK(rgb[1] == Approx(e.g).epsilon(1e-5));
    CHECK(rgb[2] == Approx(e.b).epsilon(1e-5));
  }
}

TEST_CASE("tabulation: valid bins equal single evaluations, masked bins are -1", "[nbrdf]") {
  const NeuralBrdf brdf = NeuralBrdf::Load(test::DataPath("nbrdf/merl/alum-bronze.h5"));
  const MerlBrdf table = brdf.Tabulate();
  const merl::GridGeometry& g = merl::Geometry();
  std::size_t masked_checked = 0;
  for (std::size_t bin = 0; bin < merl::kBins; bin += 997) {
    if (!g.valid[bin]) {
      for (int c = 0; c < 3; ++c) REQUIRE(table.Value(c, bin) < 0);
      ++masked_checked;
      continue;
    }
    const auto rgb = brdf.Evaluate(merl::BinCentre(merl::BinFromFlat(bin)));
    for (int c = 0; c < 3; ++c) {
      // Batched and single float32 evaluations sum in different orders: y differs by a few
      // float roundings (~1e-6 absolute) and rho = e^y - 1 moves by (1 + rho) dy.
      const double want = std::max(rgb[c], 0.0);
      REQUIRE(std::abs(table.Value(c, bin) - want) <= 5e-6 * (1 + want));
      REQUIRE(table.Value(c, bin) >= 0);
    }
  }
  CHECK(masked_checked > 0);
}

TEST_CASE("a fit with other layer shapes is refused, naming file and dataset", "[nbrdf]") {
  CHECK_THROWS_WITH(NeuralBrdf::Load(test::Fixture("wrong_shapes.h5")),
                    Catch::Contains("wrong_shapes.h5") &&
                        Catch::Contains("dense_2/dense_2/kernel:0") &&
                        Catch::Contains("(21, 30), expected (21, 21)"));
  test::TempDir dir;
  { std::ofstream(dir / "text.h5") << "not hdf5"; }
  CHECK_THROWS_WITH(NeuralBrdf::Load(dir / "text.h5"),
                    Catch::Contains("text.h5") && Catch::Contains("not an HDF5 file"));
}

TEST_CASE("evaluation is reciprocal: swapping light and camera reads the same value", "[nbrdf]") {
  // Swapping w_i and w_o maps phi_d to phi_d - pi; the fits only know [0, pi) (MERL's folded
  // domain), so the evaluation must fold, as MERL's binning does.
  const NeuralBrdf brdf = NeuralBrdf::Load(test::DataPath("nbrdf/merl/alum-bronze.h5"));
  RusinkiewiczAngles a;
  a.theta_h = DegToRad(12);
  a.theta_d = DegToRad(35);
  a.phi_d = DegToRad(70);
  const DirectionPair d = DirectionsFromRusinkiewicz(a);
  const auto forward = brdf.Evaluate(RusinkiewiczFromDirections(d.in, d.out));
  const auto swapped = brdf.Evaluate(RusinkiewiczFromDirections(d.out, d.in));
  for (int c = 0; c < 3; ++c) CHECK(swapped[c] == Approx(forward[c]).epsilon(1e-5));
}
