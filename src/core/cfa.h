// The colour filter array over a colour camera's photosites (issue 16): one convention for the
// simulated camera that draws it, the driver that records it and the HDR merge that undoes it.
// Named as GenICam names its Bayer formats, by the channels of the top-left 2 x 2 cell read row by
// row: BayerRG is R G / G B (RGGB), BayerGR is G R / B G, BayerGB is G B / R G, BayerBG is B G / G
// R.
#pragma once

#include <optional>
#include <string>

namespace acq {

enum class Cfa { kNone, kRGGB, kGRBG, kGBRG, kBGGR };

// "none", "RGGB", "GRBG", "GBRG", "BGGR" (what frames record); nullopt for another name.
const char* CfaName(Cfa cfa);
std::optional<Cfa> ParseCfa(const std::string& name);

// The channel (0 R, 1 G, 2 B) photosite (x, y) sees under the filter; -1 under none.
inline int CfaChannel(Cfa cfa, int x, int y) {
  // The top-left cell's channels, row by row, per pattern.
  static constexpr int kCell[5][4] = {
      {-1, -1, -1, -1}, {0, 1, 1, 2}, {1, 0, 2, 1}, {1, 2, 0, 1}, {2, 1, 1, 0}};
  return kCell[int(cfa)][(y & 1) * 2 + (x & 1)];
}

}  // namespace acq
