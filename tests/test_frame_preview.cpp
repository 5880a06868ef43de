// The live view's frame preview and focus aid (session/frame_preview.h): the centre at full
// block resolution, a sharpness figure that falls with defocus and ignores the exposure, and
// Bayer quads never split.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

#include "session/frame_preview.h"

using namespace acq;

namespace {

Frame FrameOf(int width, int height, PixelFormat format,
              const std::function<int(int, int)>& value) {
  Frame f;
  f.width = width;
  f.height = height;
  f.pixel_format = format;
  f.pixels.resize(std::size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      f.pixels[std::size_t(y) * width + x] = std::uint16_t(value(x, y));
  return f;
}

// A printed pattern: 8-pixel squares of 600 and 2400 on a 12-bit sensor.
int Checker(int x, int y) {
  return ((x / 8 + y / 8) % 2) ? 2400 : 600;
}

// The same pattern seen through a defocused lens: a 9 x 9 box blur.
int BlurredChecker(int x, int y) {
  int sum = 0;
  for (int dy = -4; dy <= 4; ++dy)
    for (int dx = -4; dx <= 4; ++dx) sum += Checker(x + dx + 64, y + dy + 64);
  return sum / 81;
}

}  // namespace

TEST_CASE("frame preview: the focus crop is the centre's blocks, every one", "[session]") {
  // One bright 2 x 2 block just right of and below the centre of a 640 x 480 frame.
  const Frame f = FrameOf(640, 480, PixelFormat::kMono12,
                          [](int x, int y) { return x / 2 == 160 && y / 2 == 120 ? 4095 : 0; });
  const FramePreview p = PreviewOf(f);
  REQUIRE(p.focus_width == kFocusSide);
  REQUIRE(p.focus_height == kFocusSide);
  REQUIRE(p.focus_grey.size() == std::size_t(kFocusSide) * kFocusSide);
  // The crop starts kFocusSide blocks left of and above the centre's pixel (320, 240).
  CHECK(p.focus_grey[std::size_t(kFocusSide / 2) * kFocusSide + kFocusSide / 2] == 255);
  int lit = 0;
  for (std::uint8_t g : p.focus_grey) lit += g > 0;
  CHECK(lit == 1);  // nothing skipped, nothing smeared
  // The whole-frame preview skips blocks: at most 192 a side.
  CHECK(p.width <= kPreviewMaxSide);
}

TEST_CASE("frame preview: sharpness falls with defocus and ignores the exposure", "[session]") {
  const Frame sharp = FrameOf(512, 512, PixelFormat::kMono12, Checker);
  const Frame blurred = FrameOf(512, 512, PixelFormat::kMono12, BlurredChecker);
  const Frame brighter =
      FrameOf(512, 512, PixelFormat::kMono12, [](int x, int y) { return Checker(x, y) * 3 / 2; });
  const double s_sharp = PreviewOf(sharp).sharpness, s_blurred = PreviewOf(blurred).sharpness;
  INFO("sharp " << s_sharp << ", blurred " << s_blurred);
  // A box blur of the square's width spreads every edge over the whole square: the block
  // differences shrink about 4 x, their squares far more; 2 x is a margin any defocus clears.
  CHECK(s_blurred * 2 < s_sharp);
  // 1.5 x the light scales every block and the mean alike (no pixel clips at 3600 of 4095).
  CHECK(PreviewOf(brighter).sharpness == Approx(s_sharp).epsilon(1e-12));
}

TEST_CASE("frame preview: a flat colour on a Bayer sensor has no sharpness", "[session]") {
  // RGGB sites of one flat colour: whole quads are one grey, so a split quad (an odd origin)
  // would show as a fine pattern and a sharpness above zero.
  for (int width : {640, 642, 638}) {
    const Frame f = FrameOf(width, 482, PixelFormat::kBayerRG12, [](int x, int y) {
      return (x % 2 == 0 && y % 2 == 0) ? 3000 : (x % 2 == 1 && y % 2 == 1) ? 400 : 1500;
    });
    const FramePreview p = PreviewOf(f);
    INFO("width " << width);
    CHECK(p.sharpness == 0);
    CHECK(p.focus_width == kFocusSide);
  }
}

TEST_CASE("frame preview: a frame smaller than the crop is shown whole; an empty one is no crash",
          "[session]") {
  const FramePreview small = PreviewOf(FrameOf(100, 60, PixelFormat::kMono8, Checker));
  CHECK(small.focus_width == 50);
  CHECK(small.focus_height == 30);
  CHECK(std::isfinite(small.sharpness));
  const FramePreview dark =
      PreviewOf(FrameOf(64, 64, PixelFormat::kMono8, [](int, int) { return 0; }));
  CHECK(dark.sharpness == 0);
  const FramePreview none = PreviewOf(Frame{});
  CHECK(none.focus_grey.empty());
  CHECK(none.sharpness == 0);
}
