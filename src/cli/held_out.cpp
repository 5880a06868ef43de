#include "cli/held_out.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <set>

#include "core/error.h"

namespace acq::cli {
namespace {

// The names the basis's settings list under `key` ("held_out", "training").
std::vector<std::string> SettingsNames(const BasisView& basis, const std::string& path,
                                       const char* key) {
  try {
    const YAML::Node settings = YAML::Load(std::string(basis.settings));
    std::vector<std::string> names;
    for (const auto& n : settings[key]) names.push_back(n.as<std::string>());
    return names;
  } catch (const YAML::Exception& e) {
    throw UserError(path, std::string("cannot parse the basis settings: ") + e.what(),
                    "rebuild the basis");
  }
}

// Scoring a material the basis trained on measures how well it was fitted, not how well the
// basis generalises: said on stderr, naming them (issue 18).
void WarnAboutTrained(const std::vector<MaterialFile>& materials, const BasisView& basis,
                      const std::string& path) {
  const std::vector<std::string> training = SettingsNames(basis, path, "training");
  const std::set<std::string> trained(training.begin(), training.end());
  std::string named;
  int n = 0;
  for (const MaterialFile& m : materials) {
    if (!trained.count(m.name)) continue;
    if (n < 5) named += (n > 0 ? ", " : "") + m.name;  // the first five named
    ++n;
  }
  if (n == 0) return;
  std::fprintf(stderr,
               "warning: %d of the %zu materials scored trained this basis (%s%s): their errors "
               "say how well it fits them, not how it does on materials it never saw\n",
               n, materials.size(), named.c_str(), n > 5 ? ", ..." : "");
}

}  // namespace

std::vector<MaterialFile> SelectHeldOut(const BasisView& basis, const std::string& basis_path,
                                        const Args& args, const std::string& command) {
  if (args.positionals().empty())
    throw UserError(command, "no materials given",
                    "name the materials or their folder, e.g. data/nbrdf/merl");
  std::vector<MaterialFile> materials = ListMaterials(args.positionals());
  const std::vector<std::string> held_out = SettingsNames(basis, basis_path, "held_out");
  if (args.Has("all-given") || held_out.empty()) {
    WarnAboutTrained(materials, basis, basis_path);
    return materials;
  }
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
