// The map a command works on and the basis it names (or --basis), shared by the render and
// export commands.
#pragma once

#include "brdf/basis_file.h"
#include "cli/args.h"
#include "io/svbrdf_map.h"

namespace acq::cli {

struct MapAndBasis {
  SvbrdfMap map;
  MappedBasis basis;
  std::string basis_path;
};

// --map, and --basis or the basis the map names; refuses a basis whose checksum differs.
MapAndBasis OpenMapAndBasis(const Args& args);

}  // namespace acq::cli
