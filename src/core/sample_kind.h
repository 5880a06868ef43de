// The built-in synthetic samples (sim/sample_layouts.h): named once here, because the plan
// (sim.sample) and the simulator both speak of them.
#pragma once

#include <optional>
#include <string>

namespace acq {

enum class SampleKind {
  kCard,    // the printed card: a background, two rectangles, text bars (MakeCardLayout)
  kBlend,   // material 0 to material 1 from left to right
  kMarble,  // materials 0 and 1 mixed by smooth value noise (marbled paper, wood)
  kText,    // material 1 text, strokes 2-3 pixels wide, on material 0
};

inline const char* SampleKindName(SampleKind kind) {
  switch (kind) {
    case SampleKind::kCard:
      return "card";
    case SampleKind::kBlend:
      return "blend";
    case SampleKind::kMarble:
      return "marble";
    case SampleKind::kText:
      return "text";
  }
  return "?";
}

// "card", "blend", "marble", "text"; nullopt for another name.
inline std::optional<SampleKind> ParseSampleKind(const std::string& name) {
  for (SampleKind k :
       {SampleKind::kCard, SampleKind::kBlend, SampleKind::kMarble, SampleKind::kText})
    if (name == SampleKindName(k)) return k;
  return std::nullopt;
}

// A sample laid out from a file the user describes it with (sim/sample_layouts.h): a label
// image (each pixel a material's index) or a weight image (one plane per material, named as it).
// `acq reconstruct synthetic --sample-labels|--sample-weights` and a plan's
// `sim.sample: {labels|weights: FILE}` both name one.
struct SampleFile {
  enum class Kind { kLabels, kWeights };
  Kind kind = Kind::kLabels;
  std::string path;
};

}  // namespace acq
