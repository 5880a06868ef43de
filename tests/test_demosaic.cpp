// Demosaicing an HDR mosaic (acq/demosaic.h): exact on a flat colour and on a linear ramp for
// every Bayer phase and both methods; flags spread to the pixels a flagged photosite feeds; a
// bracket of mixed filters refused by the merge.
#include <catch2/catch.hpp>

#include "acq/demosaic.h"
#include "core/error.h"

using namespace acq;

namespace {

// The mosaic of a colour image (R, G, B per pixel from `rgb(x, y)`) under a filter.
template <typename F>
HdrImage MosaicOf(Cfa cfa, int w, int h, F rgb) {
  HdrImage m;
  m.width = w;
  m.height = h;
  m.cfa = cfa;
  m.radiance.resize(std::size_t(w) * h);
  m.flag.assign(std::size_t(w) * h, kHdrOk);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m.radiance[std::size_t(y) * w + x] = float(rgb(x, y)[CfaChannel(cfa, x, y)]);
  return m;
}

constexpr Cfa kPhases[] = {Cfa::kRGGB, Cfa::kGRBG, Cfa::kGBRG, Cfa::kBGGR};
constexpr DemosaicMethod kMethods[] = {DemosaicMethod::kBilinear, DemosaicMethod::kMalvar};

}  // namespace

TEST_CASE("demosaic: a flat colour comes back exactly, every phase, both methods") {
  for (Cfa cfa : kPhases)
    for (DemosaicMethod method : kMethods) {
      INFO(CfaName(cfa) << " " << DemosaicMethodName(method));
      const HdrImage rgb = Demosaic(MosaicOf(cfa, 12, 10,
                                             [](int, int) {
                                               return std::array<double, 3>{5, 2, 0.5};
                                             }),
                                    method);
      REQUIRE(rgb.channels == 3);
      CHECK(rgb.cfa == Cfa::kNone);
      const std::size_t n = 120;
      for (std::size_t i = 0; i < n; ++i) {  // borders too: the mosaic is reflected
        CHECK(rgb.radiance[i] == Approx(5).epsilon(1e-6));
        CHECK(rgb.radiance[n + i] == Approx(2).epsilon(1e-6));
        CHECK(rgb.radiance[2 * n + i] == Approx(0.5).epsilon(1e-6));
      }
    }
}

TEST_CASE("demosaic: a linear ramp is exact away from the border (both methods are linear)") {
  auto ramp = [](int x, int y) {
    return std::array<double, 3>{1 + 0.1 * x, 2 + 0.05 * y, 3 + 0.02 * (x + y)};
  };
  for (Cfa cfa : kPhases)
    for (DemosaicMethod method : kMethods) {
      INFO(CfaName(cfa) << " " << DemosaicMethodName(method));
      const HdrImage rgb = Demosaic(MosaicOf(cfa, 16, 16, ramp), method);
      for (int y = 2; y < 14; ++y)
        for (int x = 2; x < 14; ++x)
          for (int c = 0; c < 3; ++c)
            CHECK(rgb.radiance[std::size_t(c) * 256 + std::size_t(y) * 16 + x] ==
                  Approx(ramp(x, y)[c]).epsilon(1e-5));
    }
}

TEST_CASE("demosaic: a saturated photosite flags the pixels interpolated from it") {
  HdrImage m = MosaicOf(Cfa::kRGGB, 9, 9, [](int, int) { return std::array<double, 3>{1, 1, 1}; });
  m.flag[4 * 9 + 4] = kHdrSaturated;
  const HdrImage bilinear = Demosaic(m, DemosaicMethod::kBilinear);
  CHECK(bilinear.flag[3 * 9 + 3] == kHdrSaturated);  // 3 x 3 around it
  CHECK(bilinear.flag[2 * 9 + 2] == kHdrOk);
  const HdrImage malvar = Demosaic(m, DemosaicMethod::kMalvar);
  CHECK(malvar.flag[2 * 9 + 2] == kHdrSaturated);  // 5 x 5 around it
  CHECK(malvar.flag[1 * 9 + 1] == kHdrOk);
}

TEST_CASE("HDR merge: a bracket of frames with different colour filters is refused") {
  Frame a;
  a.width = a.height = 4;
  a.pixel_format = PixelFormat::kBayerRG16;
  a.exposure_us = 1000;
  a.pixels.assign(16, 1000);
  Frame b = a;
  b.pixel_format = PixelFormat::kBayerGR16;
  b.exposure_us = 4000;
  CHECK_THROWS_WITH(MergeBracket({a, b}, {}),
                    Catch::Contains("frames of different colour filters in one bracket (BayerRG16 "
                                    "and BayerGR16)"));
  b.pixel_format = PixelFormat::kBayerRG12;  // same filter, another depth: merged
  CHECK(MergeBracket({a, b}, {}).cfa == Cfa::kRGGB);
}
