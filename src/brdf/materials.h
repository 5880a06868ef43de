// Sets of materials: files named on the command line (MERL `.binary` or neural-BRDF `.h5`),
// directories expanded, sorted by name, and split into training and held-out sets.
#pragma once

#include <string>
#include <vector>

#include "brdf/merl_brdf.h"

namespace acq {

struct MaterialFile {
  std::string name;  // file name without folder and extension: "alum-bronze"
  std::string path;
};

// Expands directories (their .binary and .h5 files), sorts by name. Throws UserError on a
// missing path, an unsupported extension, a duplicate name, or an empty result.
std::vector<MaterialFile> ListMaterials(const std::vector<std::string>& paths);

// Tabulated BRDF of a material: read (.binary) or tabulated from the network (.h5).
MerlBrdf LoadMaterial(const MaterialFile& file);

// Which materials are held out of the basis: every `every`-th by sorted name starting at
// 0-based `offset`, plus any named. every = 0 disables the periodic rule.
struct HoldOut {
  int every = 0;
  int offset = 0;
  std::vector<std::string> names;
  void Check() const;  // throws UserError on bad values
};

struct MaterialSplit {
  std::vector<MaterialFile> training, held_out;
};
// Throws UserError when a named material is not in the set or nothing is left to train on.
MaterialSplit SplitMaterials(const std::vector<MaterialFile>& all, const HoldOut& hold_out);

}  // namespace acq
