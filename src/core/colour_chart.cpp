#include "core/colour_chart.h"

#include <cmath>

namespace acq {
namespace {

double Linear(double srgb8) {
  const double v = srgb8 / 255;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

ChartPatch Patch(const char* name, double r, double g, double b) {
  return {name, {Linear(r), Linear(g), Linear(b)}};
}

}  // namespace

const std::array<ChartPatch, 24>& ColorCheckerClassic() {
  static const std::array<ChartPatch, 24> patches = {
      Patch("dark skin", 115, 82, 68),     Patch("light skin", 194, 150, 130),
      Patch("blue sky", 98, 122, 157),     Patch("foliage", 87, 108, 67),
      Patch("blue flower", 133, 128, 177), Patch("bluish green", 103, 189, 170),
      Patch("orange", 214, 126, 44),       Patch("purplish blue", 80, 91, 166),
      Patch("moderate red", 193, 90, 99),  Patch("purple", 94, 60, 108),
      Patch("yellow green", 157, 188, 64), Patch("orange yellow", 224, 163, 46),
      Patch("blue", 56, 61, 150),          Patch("green", 70, 148, 73),
      Patch("red", 175, 54, 60),           Patch("yellow", 231, 199, 31),
      Patch("magenta", 187, 86, 149),      Patch("cyan", 8, 133, 161),
      Patch("white 9.5", 243, 243, 242),   Patch("neutral 8", 200, 200, 200),
      Patch("neutral 6.5", 160, 160, 160), Patch("neutral 5", 122, 122, 121),
      Patch("neutral 3.5", 85, 85, 85),    Patch("black 2", 52, 52, 52),
  };
  return patches;
}

int ChartTurnDegrees(ChartTurn turn) {
  return 90 * int(turn);
}

std::optional<ChartTurn> ChartTurnFromDegrees(int degrees) {
  for (ChartTurn t :
       {ChartTurn::kNone, ChartTurn::kQuarter, ChartTurn::kHalf, ChartTurn::kThreeQuarter})
    if (ChartTurnDegrees(t) == degrees) return t;
  return std::nullopt;
}

namespace {

// A point turned counter-clockwise by a number of quarter turns.
Eigen::Vector2d Rotate(const Eigen::Vector2d& p, int quarters) {
  switch ((quarters % 4 + 4) % 4) {
    case 1:
      return {-p.y(), p.x()};
    case 2:
      return -p;
    case 3:
      return {p.y(), -p.x()};
    default:
      return p;
  }
}

}  // namespace

Eigen::Vector2d ChartLayout::ToChart(const Eigen::Vector2d& point) const {
  return Rotate(point, -int(turn));
}

Eigen::Vector2d ChartLayout::Centre(int patch) const {
  const int column = patch % columns, row = patch / columns;
  const double pitch = patch_mm + gap_mm;
  return Rotate({(column - (columns - 1) / 2.0) * pitch, (row - (rows - 1) / 2.0) * pitch},
                int(turn));
}

bool ChartLayout::OnChart(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d p = ToChart(point);
  return std::abs(p.x()) < WidthMm() / 2 && std::abs(p.y()) < HeightMm() / 2;
}

std::optional<int> ChartLayout::PatchAt(const Eigen::Vector2d& sample_point) const {
  if (!OnChart(sample_point)) return std::nullopt;
  const Eigen::Vector2d point = ToChart(sample_point);
  const double pitch = patch_mm + gap_mm;
  // From the chart's -x, -y corner: a gap, then a patch, every pitch.
  const double u = point.x() + WidthMm() / 2 - gap_mm, v = point.y() + HeightMm() / 2 - gap_mm;
  const int column = int(std::floor(u / pitch)), row = int(std::floor(v / pitch));
  if (column < 0 || row < 0 || column >= columns || row >= rows) return std::nullopt;
  if (u - column * pitch >= patch_mm || v - row * pitch >= patch_mm) return std::nullopt;
  return row * columns + column;
}

}  // namespace acq
