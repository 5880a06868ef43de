// The fitted analytic maps as the textures glTF and MaterialX reference (docs/export.md):
//   basecolor.png           diffuse albedo, sRGB
//   metallic_roughness.png  glTF's packing: G roughness, B metallic (0), R unused (255); linear
//   specular.png            F0 / F90 colour, sRGB (glTF KHR_materials_specular's
//                           specularColorTexture)
//   specular_weight.png     F90, the lobe's weight, linear grey in R G B and A (glTF
//                           KHR_materials_specular's specularTexture reads A)
//   coat.png                with a coat: R its weight, G its roughness, B 0; linear (glTF
//                           KHR_materials_clearcoat's clearcoatTexture reads R, its
//                           clearcoatRoughnessTexture G)
//   roughness.png           roughness alone, linear grey (for renderers that take one channel:
//                           Mitsuba's principled BSDF)
//   fit_error.exr           planes log_rmse, converged, valid (float, one a pixel)
//   fit_error.png           log_rmse in grey (0 to the 99th percentile), red where not converged
//   normal.png              the map's estimated normals when it has them (acq/map_render.h's
//                           WriteNormalPng): tangent space, (n + 1) / 2, linear; R along the
//                           sample's x (the texture's right), G along its y (the texture's up)
// Texture row 0 is the map's row 0 (glTF's v = 0 at the image's first row).
#pragma once

#include <string>

#include "acq/pbr_maps.h"

namespace acq {

struct PbrTextureNames {
  static constexpr const char* kBaseColor = "basecolor.png";
  static constexpr const char* kMetallicRoughness = "metallic_roughness.png";
  static constexpr const char* kSpecular = "specular.png";
  static constexpr const char* kSpecularWeight = "specular_weight.png";
  static constexpr const char* kCoat = "coat.png";
  static constexpr const char* kRoughness = "roughness.png";
  static constexpr const char* kFitError = "fit_error.exr";
  static constexpr const char* kFitErrorPng = "fit_error.png";
  static constexpr const char* kNormal = "normal.png";
};

// The optional textures an export has, which the glTF and MaterialX documents reference.
struct PbrTextureSet {
  bool normal_map = false;  // normal.png
  bool coat = false;        // coat.png: some pixel has a coat
};

// Writes every texture above but normal.png; returns which optional ones it wrote.
// Throws UserError naming the file when one cannot be written.
PbrTextureSet WritePbrTextures(const PbrMaps& maps, const std::string& dir);

}  // namespace acq
