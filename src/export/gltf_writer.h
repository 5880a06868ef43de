// The fitted maps as a glTF 2.0 asset (docs/export.md): one quad the size of the sample, lying
// in glTF's XZ plane with its normal along +Y (up), UVs so the textures' first row is the map's
// first row, and a metallic-roughness material with KHR_materials_specular carrying the fitted
// F0 / F90 colour (specularColorFactor 1 / 0.04 against glTF's dielectric 0.04 at ior 1.5, so
// that it is the texture's value) and F90 (specularTexture), and, where the fit has a coat,
// KHR_materials_clearcoat. Files: material.gltf, quad.bin; the textures of pbr_textures.h.
#pragma once

#include <string>

#include "export/pbr_textures.h"

namespace acq {

inline constexpr const char* kGltfFile = "material.gltf";
inline constexpr const char* kGltfBuffer = "quad.bin";

// Throws UserError naming the file when one cannot be written.
// `textures`: the optional textures to reference (normal.png as the normalTexture, coat.png).
void WriteGltf(const std::string& dir, double width_mm, double height_mm, const std::string& name,
               const PbrTextureSet& textures);

}  // namespace acq
