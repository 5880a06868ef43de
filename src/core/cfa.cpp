#include "core/cfa.h"

namespace acq {

const char* CfaName(Cfa cfa) {
  switch (cfa) {
    case Cfa::kNone:
      return "none";
    case Cfa::kRGGB:
      return "RGGB";
    case Cfa::kGRBG:
      return "GRBG";
    case Cfa::kGBRG:
      return "GBRG";
    case Cfa::kBGGR:
      return "BGGR";
  }
  return "?";
}

std::optional<Cfa> ParseCfa(const std::string& name) {
  for (Cfa c : {Cfa::kNone, Cfa::kRGGB, Cfa::kGRBG, Cfa::kGBRG, Cfa::kBGGR})
    if (name == CfaName(c)) return c;
  return std::nullopt;
}

}  // namespace acq
