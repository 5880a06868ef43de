// The colour matrix from a chart (acq/colour_chart_fit.h), on synthetic images of a known camera
// under a known light: the fit recovers the camera's inverse cross-talk and the light's colour;
// covered or saturated patches are dropped by name; too few left is refused.
#include <catch2/catch.hpp>

#include <Eigen/LU>
#include <cmath>

#include "acq/colour_chart_fit.h"
#include "core/error.h"

using namespace acq;

namespace {

constexpr int kSize = 200;
constexpr double kPxPerMm = 4.5;  // the chart (37 x 25 mm) spans 167 x 113 px

struct SyntheticCamera {
  Eigen::Matrix3d camera_from_rec709;
  Eigen::Vector3d light;
};

SampleToImage Orthographic() {
  return [](const Eigen::Vector2d& p) -> std::optional<Eigen::Vector2d> {
    return Eigen::Vector2d(kSize / 2.0 + kPxPerMm * p.x(), kSize / 2.0 + kPxPerMm * p.y());
  };
}

// The chart's (or, with `white`, a Spectralon's) camera RGB under a light that falls off
// across the image, as a demosaiced HDR image.
HdrImage Render(const SyntheticCamera& cam, bool white, const ChartLayout& layout = {}) {
  HdrImage im;
  im.width = im.height = kSize;
  im.channels = 3;
  const std::size_t n = std::size_t(kSize) * kSize;
  im.radiance.assign(3 * n, 0);
  im.flag.assign(n, kHdrOk);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Eigen::Vector2d p((x - kSize / 2.0) / kPxPerMm, (y - kSize / 2.0) / kPxPerMm);
      Eigen::Vector3d reflectance = Eigen::Vector3d::Constant(white ? 0.99 : 0.03);
      if (!white)
        if (const std::optional<int> patch = layout.PatchAt(p)) {
          const auto& rgb = ColorCheckerClassic()[std::size_t(*patch)].rgb;
          reflectance = {rgb[0], rgb[1], rgb[2]};
        }
      const double falloff = 1.0 / (1.0 + 0.002 * (p.x() + 30) * (p.x() + 30));
      const Eigen::Vector3d camera =
          cam.camera_from_rec709 * reflectance.cwiseProduct(cam.light) * 500 * falloff;
      for (int c = 0; c < 3; ++c)
        im.radiance[c * n + std::size_t(y) * kSize + x] = float(camera[c]);
    }
  return im;
}

SyntheticCamera PlausibleCamera() {
  SyntheticCamera c;
  c.camera_from_rec709 << 0.78, 0.18, 0.04, 0.12, 0.76, 0.12, 0.04, 0.22, 0.74;
  c.light = {1.38, 1.0, 0.55};
  return c;
}

// Paints a patch's left half as the chart's black body: covered.
void Cover(HdrImage* im, int patch, const ChartLayout& layout = {}) {
  const std::size_t n = std::size_t(kSize) * kSize;
  const Eigen::Vector2d c = layout.Centre(patch);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Eigen::Vector2d p((x - kSize / 2.0) / kPxPerMm, (y - kSize / 2.0) / kPxPerMm);
      if (std::abs(p.y() - c.y()) < layout.patch_mm / 2 && p.x() < c.x() &&
          p.x() > c.x() - layout.patch_mm / 2)
        for (int ch = 0; ch < 3; ++ch) im->radiance[ch * n + std::size_t(y) * kSize + x] *= 0.05f;
    }
}

// Lays a uniform grey card (albedo 0.18, as the camera sees it under the light) over a patch
// and its surround: the patch is uniform, of the wrong colour.
void CoverWhole(HdrImage* im, const SyntheticCamera& cam, int patch,
                const ChartLayout& layout = {}) {
  const std::size_t n = std::size_t(kSize) * kSize;
  const Eigen::Vector2d c = layout.Centre(patch);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const Eigen::Vector2d p((x - kSize / 2.0) / kPxPerMm, (y - kSize / 2.0) / kPxPerMm);
      if ((p - c).cwiseAbs().maxCoeff() > layout.patch_mm / 2 + layout.gap_mm / 2) continue;
      const double falloff = 1.0 / (1.0 + 0.002 * (p.x() + 30) * (p.x() + 30));
      const Eigen::Vector3d camera = cam.camera_from_rec709 * (0.18 * cam.light) * 500 * falloff;
      for (int ch = 0; ch < 3; ++ch)
        im->radiance[ch * n + std::size_t(y) * kSize + x] = float(camera[ch]);
    }
}

}  // namespace

TEST_CASE("colour chart: the fit undoes the camera's cross-talk and the light's colour") {
  const SyntheticCamera cam = PlausibleCamera();
  const ChartFit fit =
      FitColourChart(Render(cam, false), Render(cam, true), Orthographic(), "test chart");
  CHECK(fit.used == 24);
  // A x (cross-talk x diag(light)) must be a multiple of the identity: the colours come back,
  // whatever the scale (the Spectralon's 0.99 and the fall-off, divided out). Exact data: 1e-6.
  const Eigen::Matrix3d product =
      fit.rec709_from_camera * cam.camera_from_rec709 * cam.light.asDiagonal();
  const Eigen::Matrix3d unit = product / product(1, 1);
  CHECK((unit - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6);
  CHECK(fit.max_delta_e2000 < 0.05);  // the chart's references rounded to 8-bit sRGB: exact
}

TEST_CASE("colour chart: covered or saturated patches are dropped by name; too few refused") {
  const SyntheticCamera cam = PlausibleCamera();
  const HdrImage white = Render(cam, true);
  HdrImage chart = Render(cam, false);
  Cover(&chart, 2);   // blue sky
  Cover(&chart, 13);  // green
  // Saturated photosites at the centre of "orange" (patch 7).
  const Eigen::Vector2d orange = ChartLayout().Centre(6);
  chart.flag[std::size_t(std::lround(kSize / 2 + kPxPerMm * orange.y())) * kSize +
             std::size_t(std::lround(kSize / 2 + kPxPerMm * orange.x()))] = kHdrSaturated;
  const ChartFit fit = FitColourChart(chart, white, Orthographic(), "test chart");
  CHECK(fit.used == 21);
  CHECK(fit.patches[2].dropped.find("not uniform") != std::string::npos);
  CHECK(fit.patches[13].dropped.find("not uniform") != std::string::npos);
  CHECK(fit.patches[6].dropped == "saturated or dark");
  CHECK(fit.max_delta_e2000 < 0.05);  // the 21 left still fit exactly

  for (int patch = 0; patch < 14; ++patch) Cover(&chart, patch);
  try {
    FitColourChart(chart, white, Orthographic(), "test chart");
    FAIL("a chart with 10 usable patches was fitted");
  } catch (const UserError& e) {
    CHECK(std::string(e.what()).find("only 10 of 24 colour chart patches are usable") !=
          std::string::npos);
    CHECK(std::string(e.what()).find("dark skin: not uniform") != std::string::npos);
  }
}

TEST_CASE("colour chart: patches wholly under a grey card are found by the fit and dropped") {
  const SyntheticCamera cam = PlausibleCamera();
  const HdrImage white = Render(cam, true);
  HdrImage chart = Render(cam, false);
  // Uniform patches of the wrong colour: the spread test cannot see them.
  for (int patch : {0, 1, 6, 7}) CoverWhole(&chart, cam, patch);  // dark skin ... purplish blue
  const ChartFit fit = FitColourChart(chart, white, Orthographic(), "test chart");
  CHECK(fit.used == 20);
  for (int patch : {0, 1, 6, 7}) {
    INFO(fit.patches[std::size_t(patch)].name << ": " << fit.patches[std::size_t(patch)].dropped);
    CHECK(fit.patches[std::size_t(patch)].dropped.find("from its reference colour after the fit") !=
          std::string::npos);
  }
  // The 20 left fit exactly (as the whole chart does): the covered ones no longer pull the fit.
  CHECK(fit.max_delta_e2000 < 0.05);
  const Eigen::Matrix3d product =
      fit.rec709_from_camera * cam.camera_from_rec709 * cam.light.asDiagonal();
  CHECK((product / product(1, 1) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6);

  // Covered past the minimum: refused, naming the patches and why.
  for (int patch = 8; patch < 18; ++patch) CoverWhole(&chart, cam, patch);
  try {
    FitColourChart(chart, white, Orthographic(), "test chart");
    FAIL("a chart with most patches covered was fitted");
  } catch (const UserError& e) {
    CHECK(std::string(e.what()).find("of 24 colour chart patches are usable") != std::string::npos);
    CHECK(std::string(e.what()).find("after the fit") != std::string::npos);
  }
}

TEST_CASE("colour chart: a chart laid turned is fitted as laid, and said") {
  const SyntheticCamera cam = PlausibleCamera();
  for (ChartTurn turn :
       {ChartTurn::kNone, ChartTurn::kQuarter, ChartTurn::kHalf, ChartTurn::kThreeQuarter}) {
    CAPTURE(ChartTurnDegrees(turn));
    ChartLayout laid;
    laid.turn = turn;
    const ChartFit fit =
        FitColourChart(Render(cam, false, laid), Render(cam, true), Orthographic(), "test chart");
    CHECK(fit.turned == turn);
    CHECK(fit.used == 24);
    CHECK(fit.patches[0].name == std::string("dark skin"));
    // Exact to rounding: every patch read is its own patch.
    const Eigen::Matrix3d product =
        fit.rec709_from_camera * cam.camera_from_rec709 * cam.light.asDiagonal();
    CHECK((product / product(1, 1) - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6);
  }
}

TEST_CASE("colour chart: the layout turned keeps each patch where the turn takes it") {
  ChartLayout laid;
  for (int quarters = 0; quarters < 4; ++quarters) {
    laid.turn = ChartTurn(quarters);
    CHECK(ChartTurnFromDegrees(ChartTurnDegrees(laid.turn)) == laid.turn);
    for (int i = 0; i < 24; ++i) CHECK(laid.PatchAt(laid.Centre(i)) == i);
  }
  laid.turn = ChartTurn::kQuarter;  // dark skin, at (-x, -y) as laid, goes to (+x, -y)
  CHECK(laid.Centre(0).x() > 0);
  CHECK(laid.Centre(0).y() < 0);
  CHECK_FALSE(ChartTurnFromDegrees(45));
}
