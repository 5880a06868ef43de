// Synthetic samples beyond the printed card (issue 17): a two-material blend across the sample,
// a noise-driven marbled mix, fine text, and samples the user describes in files (a label image
// or per-material weight images). A mixed pixel's BRDF is the weighted sum of its materials';
// weights are quantised to 1/16 so that every distinct mixture is one derived material with a
// label of its own: the renderer, the scoring and the per-material report then treat a blend
// exactly as they treat a card of inks (and the truth of each mixture is exact, not sampled).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/sample_kind.h"
#include "sim/synthetic_svbrdf.h"

namespace acq::sim {

// A mixture: (base material index, weight) pairs, weights summing to one.
using Mixture = std::vector<std::pair<int, double>>;

struct MixedSample {
  SyntheticSvbrdf layout;         // labels index `mixtures`
  std::vector<Mixture> mixtures;  // at most 255
  // "white-paint" for a pure material, "0.25 white-paint + 0.75 brass" for a mixture.
  std::vector<std::string> Names(const std::vector<std::string>& materials) const;
  // Ground truths of the mixtures from those of the base materials (which must outlive them).
  std::vector<GroundTruth> Truths(const std::vector<GroundTruth>& materials) const;
  // Tables of the mixtures from the base materials' tables (bins without data stay without).
  std::vector<MerlBrdf> Tables(const std::vector<MerlBrdf>& materials) const;
};

// A built-in sample of `materials` base materials (the blend, marble and text use the first
// two; the card all of them). Deterministic for a seed. Throws UserError when too few.
MixedSample MakeSample(SampleKind kind, int width, int height, double sample_size_mm, int materials,
                       std::uint64_t seed);

// A sample from a label image: an 8- or 16-bit grey PNG whose value is the material's index in
// the list of `materials` names, or an EXR with a "label" channel. UserError naming the file
// for a label with no material, an unreadable file or an empty image.
MixedSample ReadSampleLabels(const std::string& path, int materials, double sample_size_mm);

// A sample from per-material weights: an EXR with one channel per material, named as the
// materials are. UserError naming the file for a missing channel, a negative weight or
// weights that do not sum to one (within 1%), naming the first pixel where they do not.
MixedSample ReadSampleWeights(const std::string& path, const std::vector<std::string>& materials,
                              double sample_size_mm);

// The sample a SampleFile describes (ReadSampleLabels or ReadSampleWeights), its materials named
// `materials` (a weight image's planes are named as they are).
MixedSample ReadSampleFile(const SampleFile& file, const std::vector<std::string>& materials,
                           double sample_size_mm);

}  // namespace acq::sim
