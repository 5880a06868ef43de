#include "cli/map_and_basis.h"

#include "core/error.h"

namespace acq::cli {

MapAndBasis OpenMapAndBasis(const Args& args) {
  SvbrdfMap map = ReadSvbrdfMap(args.Required("map"));
  const std::string basis_path = args.Get("basis", map.info.basis);
  MappedBasis basis = MappedBasis::Open(basis_path);
  if (basis.Checksum() != map.info.basis_crc32)
    throw UserError(basis_path,
                    "is not the basis the map was reconstructed with (checksum differs from the "
                    "map's acqBasisCrc32)",
                    "give --basis the file the map names: " + map.info.basis);
  return {std::move(map), std::move(basis), basis_path};
}

}  // namespace acq::cli
