#include "brdf/materials.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "brdf/neural_brdf.h"
#include "core/error.h"

namespace acq {
namespace fs = std::filesystem;
namespace {

bool IsMaterialExtension(const fs::path& p) {
  return p.extension() == ".binary" || p.extension() == ".h5";
}

}  // namespace

std::vector<MaterialFile> ListMaterials(const std::vector<std::string>& paths) {
  std::vector<MaterialFile> out;
  for (const std::string& arg : paths) {
    const fs::path p(arg);
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      for (const auto& entry : fs::directory_iterator(p)) {
        if (entry.is_regular_file() && IsMaterialExtension(entry.path()))
          out.push_back({entry.path().stem().string(), entry.path().string()});
      }
    } else if (fs::is_regular_file(p, ec)) {
      if (!IsMaterialExtension(p))
        throw UserError(arg, "unsupported material file type '" + p.extension().string() + "'",
                        "give MERL .binary files, neural-BRDF .h5 fits, or folders of them");
      out.push_back({p.stem().string(), p.string()});
    } else {
      throw UserError(arg, "no such file or folder", "check the path");
    }
  }
  std::sort(out.begin(), out.end(),
            [](const MaterialFile& a, const MaterialFile& b) { return a.name < b.name; });
  for (std::size_t i = 1; i < out.size(); ++i) {
    if (out[i].name == out[i - 1].name)
      throw UserError(
          out[i].path,
          "material '" + out[i].name + "' is given twice (also " + out[i - 1].path + ")",
          "give each material once");
  }
  if (out.empty()) {
    std::string where;
    for (const auto& a : paths) where += (where.empty() ? "" : " ") + a;
    throw UserError(where.empty() ? "materials" : where,
                    "empty material set: no .binary or .h5 files",
                    "point at the folder of fits, e.g. data/nbrdf/merl");
  }
  return out;
}

MerlBrdf LoadMaterial(const MaterialFile& file) {
  if (fs::path(file.path).extension() == ".h5") return NeuralBrdf::Load(file.path).Tabulate();
  return ReadMerlBinary(file.path);
}

void HoldOut::Check() const {
  if (every < 0) throw UserError("--holdout-every", "must be >= 0 (0 disables it)");
  if (offset < 0 || (every > 0 && offset >= every))
    throw UserError("--holdout-offset", "must be in [0, every)",
                    "e.g. --holdout-every 10 --holdout-offset 5");
}

MaterialSplit SplitMaterials(const std::vector<MaterialFile>& all, const HoldOut& hold_out) {
  hold_out.Check();
  std::set<std::string> named(hold_out.names.begin(), hold_out.names.end());
  for (const std::string& n : named) {
    if (std::none_of(all.begin(), all.end(), [&](const MaterialFile& m) { return m.name == n; }))
      throw UserError("--holdout " + n, "no material of that name in the set",
                      "names are file names without extension, e.g. alum-bronze");
  }
  MaterialSplit split;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const bool periodic = hold_out.every > 0 && int(i % hold_out.every) == hold_out.offset;
    (periodic || named.count(all[i].name) ? split.held_out : split.training).push_back(all[i]);
  }
  if (split.training.empty())
    throw UserError("materials", "every material is held out; nothing is left to train on",
                    "hold out fewer materials");
  return split;
}

}  // namespace acq
