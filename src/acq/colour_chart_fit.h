// The colour matrix from a captured colour chart (issue 16; docs/colour.md): the chart's patches
// located through the calibrated camera at its pose, each patch's camera RGB divided by the grey
// of the Spectralon captured at the same pose and pixels (which removes the light's fall-off, not
// its colour), and the 3 x 3 matrix A that takes those to the patches' reference reflectances by
// least squares. A = diag(1 / light) x (camera's cross-talk)^-1 up to a scale: applied to every
// image, the light's colour goes too, and the Spectralon division per channel stays exact.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acq/hdr.h"
#include "core/colour_chart.h"

namespace acq {

struct ChartPatchFit {
  std::string name;
  bool used = false;
  std::string dropped;          // why it was left out, when not used
  std::array<double, 3> rgb{};  // corrected: A x its camera RGB (linear Rec. 709)
  double delta_e2000 = 0;       // against its reference, when used
};

struct ChartFit {
  Eigen::Matrix3d rec709_from_camera = Eigen::Matrix3d::Identity();
  std::vector<ChartPatchFit> patches;  // the chart's 24, in its order
  int used = 0;
  double max_delta_e2000 = 0, median_delta_e2000 = 0;
  // How the chart was found laid, when not as the layout says: read and fitted as laid.
  ChartTurn turned = ChartTurn::kNone;
};

// Fewer usable patches than this and the fit is refused: 9 unknowns, and the patches must span
// the hues (a chart half covered fits its visible half only).
inline constexpr int kMinChartPatches = 12;

// A patch the least-squares fit misses by more than this (CIEDE2000) is not the patch the layout
// says (wholly covered by something uniform, or the chart laid elsewhere): dropped, and the
// rest fitted again. The simulated camera leaves 1.05 at worst; a linear fit of a real camera is
// commonly reported to leave a few units on the most saturated patches (not measured here); a
// grey card wholly over a coloured patch left 18-28 in tests/test_colour_chart.cpp.
inline constexpr double kMaxChartResidual = 10;

// A point on the sample plane (mm) to the image (pixels), or nullopt where not visible.
using SampleToImage = std::function<std::optional<Eigen::Vector2d>(const Eigen::Vector2d&)>;

// `chart` and `spectralon`: demosaiced camera RGB (3 planes) at the same pose. A patch is
// dropped (named, with why) when a pixel of its centre is flagged or off the image, or its
// values vary beyond what noise explains (covered, or not where the layout says), or the fit
// misses it by more than kMaxChartResidual (wholly covered by something uniform). A chart laid
// turned by a quarter, half or three quarters is fitted as laid (ChartFit::turned), tried only
// when too few patches fit as the layout says. Throws UserError naming `where` when fewer than
// kMinChartPatches remain every way.
ChartFit FitColourChart(const HdrImage& chart, const HdrImage& spectralon,
                        const SampleToImage& to_image, const std::string& where,
                        const ChartLayout& layout = {});

}  // namespace acq
