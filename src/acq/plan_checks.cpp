#include "acq/plan_checks.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include "brdf/basis_file.h"
#include "core/error.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

bool Inside(const fs::path& path, const fs::path& folder) {
  const auto [f, p] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
  return f == folder.end();
}

}  // namespace

void CheckOutputFolder(const std::string& folder, const std::string& where) {
  std::error_code ec;
  const fs::path path = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (folder.empty() || ec)
    throw UserError(where, "output '" + folder + "' is not a usable path",
                    "give the session a folder of its own, like sessions/card-001");
  if (fs::exists(path, ec) && !fs::is_directory(path, ec))
    throw UserError(where, "output " + path.string() + " exists and is not a folder",
                    "give the session a folder of its own (it is created if absent)");
  for (const char* system :
       {"/", "/dev", "/proc", "/sys", "/usr", "/etc", "/bin", "/sbin", "/lib", "/boot", "/run"}) {
    const bool root_itself = std::string(system) == "/" && path == fs::path("/");
    if (root_itself || (std::string(system) != "/" && Inside(path, system)))
      throw UserError(where, "output " + path.string() + " is a system folder",
                      "give the session a folder of its own, like sessions/card-001");
  }
#ifdef ACQ_SOURCE_DIR
  const fs::path source = fs::weakly_canonical(ACQ_SOURCE_DIR, ec);
  if (!ec && Inside(path, source)) {
    const fs::path relative = path.lexically_relative(source);
    const std::string top = relative.empty() ? "" : relative.begin()->string();
    if (top != "out" && top.rfind("build", 0) != 0)
      throw UserError(where, "output " + path.string() + " is inside the project's source tree",
                      "write sessions under " + (source / "out").string() +
                          " (ignored by git) or outside the project");
  }
#endif
  // Writable: the folder, or the nearest folder above it that exists (it is created from there).
  fs::path existing = path;
  while (!fs::exists(existing, ec) && existing.has_parent_path() &&
         existing != existing.root_path())
    existing = existing.parent_path();
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw UserError(where,
                    "output " + path.string() + " cannot be written (" + existing.string() +
                        " is not writable)",
                    "choose a folder you can write, or fix its permissions");
}

void CheckPlanResources(const Plan& plan) {
  CheckOutputFolder(plan.output, plan.path + ": output");
  const MappedBasis mapped = [&] {
    try {
      return MappedBasis::Open(plan.reconstruction.basis_file);
    } catch (const UserError& e) {
      throw UserError(plan.reconstruction.basis_where,
                      std::string("reconstruction.basis: ") + e.what(),
                      "build one with `acq basis build` (README)");
    }
  }();
  const int components = int(mapped.View().components);
  const int directions = plan.optimize_n > 0 && plan.directions.empty()
                             ? plan.optimize_n
                             : int(plan.directions.size());
  if (plan.reconstruction.components > components)
    throw UserError(plan.reconstruction.components_where,
                    "reconstruction.k is " + std::to_string(plan.reconstruction.components) +
                        " but the basis " + plan.reconstruction.basis_file + " has " +
                        std::to_string(components) + " components",
                    "set reconstruction.k to at most " + std::to_string(components));
  if (plan.reconstruction.components > directions)
    throw UserError(plan.reconstruction.components_where,
                    "reconstruction.k is " + std::to_string(plan.reconstruction.components) +
                        " but the plan has " + std::to_string(directions) +
                        " directions: the per-pixel solve would be "
                        "underdetermined",
                    "set reconstruction.k to at most the number of directions");
}

}  // namespace acq
