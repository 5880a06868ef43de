// Colour conventions (core/colour.h, core/cfa.h): CIEDE2000 against its published test data,
// CIELAB's white and black, the Bayer phases.
#include <catch2/catch.hpp>

#include "core/cfa.h"
#include "core/colour.h"

using namespace acq;
using Catch::WithinAbs;

// G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference formula: implementation notes,
// supplementary test data, and mathematical observations", Color Res. Appl. 30(1), 2005, Table 1:
// L1, a1, b1, L2, a2, b2, Delta E00 (to 4 decimals).
static const double kSharmaPairs[34][7] = {
    {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
    {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
    {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
    {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
    {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
    {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
    {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
    {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
    {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
    {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
    {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
    {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
    {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
    {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
    {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
    {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
    {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
    {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
    {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
};

TEST_CASE("CIEDE2000 gives Sharma, Wu and Dalal's 34 published differences") {
  for (const auto& p : kSharmaPairs) {
    const Lab x{p[0], p[1], p[2]}, y{p[3], p[4], p[5]};
    INFO("pair " << p[0] << " " << p[1] << " " << p[2] << " / " << p[3] << " " << p[4] << " "
                 << p[5]);
    // The table rounds to 4 decimals: half a unit of the last place.
    CHECK_THAT(DeltaE2000(x, y), WithinAbs(p[6], 5e-5));
    CHECK_THAT(DeltaE2000(y, x), WithinAbs(p[6], 5e-5));  // symmetric
  }
}

TEST_CASE("CIELAB of linear Rec. 709: white is L 100, grey is neutral, black is 0") {
  const Lab white = LabFromLinearRec709({1, 1, 1});
  // The sRGB matrix's rows sum to the D65 white it divides by, to 4 digits.
  CHECK_THAT(white.L, WithinAbs(100, 1e-6));
  CHECK_THAT(white.a, WithinAbs(0, 0.02));
  CHECK_THAT(white.b, WithinAbs(0, 0.02));
  const Lab grey = LabFromLinearRec709({0.18, 0.18, 0.18});
  CHECK_THAT(grey.L, WithinAbs(49.5, 0.1));  // 18% grey is L* 49.5
  CHECK_THAT(LabFromLinearRec709({0, 0, 0}).L, WithinAbs(0, 1e-12));
  // Saturated red is far from orange-red, and a colour is zero from itself.
  const Lab red = LabFromLinearRec709({1, 0, 0});
  CHECK(DeltaE2000(red, LabFromLinearRec709({1, 0.2, 0})) > 5);
  CHECK(DeltaE2000(red, red) == 0);
}

TEST_CASE("Bayer phases: each 2 x 2 cell holds one R, two G and one B where GenICam says") {
  CHECK(CfaChannel(Cfa::kRGGB, 0, 0) == 0);
  CHECK(CfaChannel(Cfa::kRGGB, 1, 1) == 2);
  CHECK(CfaChannel(Cfa::kGRBG, 1, 0) == 0);
  CHECK(CfaChannel(Cfa::kGBRG, 0, 1) == 0);
  CHECK(CfaChannel(Cfa::kBGGR, 1, 1) == 0);
  CHECK(CfaChannel(Cfa::kNone, 3, 5) == -1);
  for (Cfa cfa : {Cfa::kRGGB, Cfa::kGRBG, Cfa::kGBRG, Cfa::kBGGR}) {
    int count[3] = {0, 0, 0};
    for (int y = 10; y < 12; ++y)
      for (int x = 7; x < 9; ++x) ++count[CfaChannel(cfa, x, y)];
    CHECK(count[0] == 1);
    CHECK(count[1] == 2);
    CHECK(count[2] == 1);
    CHECK(ParseCfa(CfaName(cfa)) == cfa);
  }
  CHECK(!ParseCfa("RGBG"));
}
