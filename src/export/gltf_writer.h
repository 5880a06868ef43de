// The fitted maps as a glTF 2.0 asset (docs/export.md): one quad the size of the sample, lying
// in glTF's XZ plane with its normal along +Y (up), UVs so the textures' first row is the map's
// first row, and a metallic-roughness material with KHR_materials_specular carrying the fitted
// F0 colour (specularColorFactor 1 / 0.04 against glTF's dielectric 0.04 at ior 1.5, so that
// F0 = the texture's value). Files: material.gltf, quad.bin; the textures of pbr_textures.h.
#pragma once

#include <string>

namespace acq {

inline constexpr const char* kGltfFile = "material.gltf";
inline constexpr const char* kGltfBuffer = "quad.bin";

// Throws UserError naming the file when one cannot be written.
// `normal_map`: reference normal.png (pbr_textures.h) as the material's normalTexture.
void WriteGltf(const std::string& dir, double width_mm, double height_mm, const std::string& name,
               bool normal_map);

}  // namespace acq
