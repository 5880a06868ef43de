#include "cli/held_out.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <set>

#include "core/error.h"

namespace acq::cli {
namespace {

std::vector<std::string> HeldOutNames(const BasisView& basis, const std::string& path) {
  try {
    const YAML::Node settings = YAML::Load(std::string(basis.settings));
    std::vector<std::string> names;
    for (const auto& n : settings["held_out"]) names.push_back(n.as<std::string>());
    return names;
  } catch (const YAML::Exception& e) {
    throw UserError(path, std::string("cannot parse the basis settings: ") + e.what(),
                    "rebuild the basis");
  }
}

}  // namespace

std::vector<MaterialFile> SelectHeldOut(const BasisView& basis, const std::string& basis_path,
                                        const Args& args, const std::string& command) {
  if (args.positionals().empty())
    throw UserError(command, "no materials given",
                    "name the materials or their folder, e.g. data/nbrdf/merl");
  std::vector<MaterialFile> materials = ListMaterials(args.positionals());
  const std::vector<std::string> held_out = HeldOutNames(basis, basis_path);
  if (args.Has("all-given") || held_out.empty()) return materials;
  const std::set<std::string> keep(held_out.begin(), held_out.end());
  std::erase_if(materials, [&](const MaterialFile& m) { return !keep.count(m.name); });
  if (materials.empty())
    throw UserError(command, "none of the basis's held-out materials is among those given",
                    "give the folder the basis was built from, or use --all-given");
  if (materials.size() != keep.size())
    std::fprintf(stderr, "warning: only %zu of the basis's %zu held-out materials are given\n",
                 materials.size(), keep.size());
  return materials;
}

}  // namespace acq::cli
