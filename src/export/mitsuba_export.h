// The data-driven map as a Mitsuba 3 scene (docs/export.md): the map's coefficients
// (coefficients.bin: float32, rows, then columns, then R G B, then k), scene.json (the map's size,
// pixel size, k, row lookup, the basis's path and checksum, the light and camera arms), the
// BSDF plugin acq_svbrdf.py and the scene script render.py (both embedded in acq at build time).
#pragma once

#include <string>

#include "core/gantry_geometry.h"
#include "io/svbrdf_map.h"

namespace acq {

struct MitsubaExport {
  std::string basis_path;  // absolute: the scene is rendered from anywhere
  ArmAngles arms;          // the light and camera of the scene
  double camera_distance_mm = 1000, light_distance_mm = 1000;
};

// Throws UserError naming the file when one cannot be written.
void WriteMitsubaExport(const SvbrdfMap& map, const MitsubaExport& options, const std::string& dir);

}  // namespace acq
