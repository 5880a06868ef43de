#include <cstdio>
#include <filesystem>

#include "brdf/materials.h"
#include "cli/args.h"
#include "cli/commands.h"

namespace acq::cli {

int MaterialConvert(const Argv& argv) {
  const Args args("acq material convert", argv, {"o"}, {});
  const std::string out = args.Required("o");
  const std::vector<MaterialFile> materials = ListMaterials(args.positionals());
  std::filesystem::create_directories(out);
  for (const MaterialFile& m : materials) {
    const std::string path = out + "/" + m.name + ".binary";
    WriteMerlBinary(LoadMaterial(m), path);
    std::printf("%s -> %s\n", m.path.c_str(), path.c_str());
  }
  return 0;
}

}  // namespace acq::cli
