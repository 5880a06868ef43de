// The colour chart (issue 16): an X-Rite ColorChecker Classic's 24 patches, their reference
// colours and where each lies on the chart, declared once for the simulated instrument that
// renders it and the processing that reads it back. A chart lies flat on the sample plane,
// centred, its rows along the sample frame's x: patch 1 (dark skin) at the -x, -y corner, patches
// 1-6 the first row, ..., 19-24 (white to black) the last, at +y.
#pragma once

#include <array>
#include <optional>

#include <Eigen/Core>

namespace acq {

struct ChartPatch {
  const char* name;
  std::array<double, 3> rgb;  // linear Rec. 709 reflectance (white 9.5 is 0.90)
};

// X-Rite's nominal sRGB values of the ColorChecker Classic (D65; the chart's maker and
// BabelColor publish them), converted once to linear reflectance by the sRGB transfer function.
const std::array<ChartPatch, 24>& ColorCheckerClassic();

// How the chart is turned on the sample plane from the layout's orientation, counter-clockwise
// (from the sample frame's +x towards +y). An operator can lay a chart any of these ways; a chart
// lies face up, so it cannot be laid mirrored.
enum class ChartTurn { kNone, kQuarter, kHalf, kThreeQuarter };
int ChartTurnDegrees(ChartTurn turn);
std::optional<ChartTurn> ChartTurnFromDegrees(int degrees);  // 0, 90, 180 or 270

struct ChartLayout {
  ChartTurn turn = ChartTurn::kNone;  // every position below is turned with the chart
  int columns = 6, rows = 4;
  double patch_mm = 5, gap_mm = 1;  // fits the 40 mm sample of the example plans
  double WidthMm() const { return columns * patch_mm + (columns + 1) * gap_mm; }
  double HeightMm() const { return rows * patch_mm + (rows + 1) * gap_mm; }
  // Patch i's (0-based) centre on the sample plane.
  Eigen::Vector2d Centre(int patch) const;
  // The patch at a point of the sample plane, or nullopt between patches and off the chart.
  std::optional<int> PatchAt(const Eigen::Vector2d& point) const;
  bool OnChart(const Eigen::Vector2d& point) const;

 private:
  Eigen::Vector2d ToChart(const Eigen::Vector2d& point) const;  // sample plane -> chart, unturned
};

}  // namespace acq
