// The fitted maps as a MaterialX 1.39 document (material.mtlx; docs/export.md): a
// standard_surface whose base colour, specular roughness, specular colour and IOR come from the
// textures of pbr_textures.h. standard_surface's dielectric specular is tinted by a colour and
// set by an IOR; the fitted F0 colour becomes the tint F0 / max(F0) and the IOR
// (1 + sqrt(max F0)) / (1 - sqrt(max F0)), computed in the document's node graph, and its
// specular weight is F90, so the reflectance at normal incidence is the fitted one and at grazing
// the fitted F90 (exactly in the brightest channel; the others' F90 are tinted). A coat, where the
// fit has one, is standard_surface's coat (GGX, IOR 1.5, white). MaterialX's texture v = 0 is the
// image's bottom row: a mesh takes v = 1 - v of glTF's quad.
#pragma once

#include <string>

#include "export/pbr_textures.h"

namespace acq {

inline constexpr const char* kMaterialXFile = "material.mtlx";

// `name`: the material's name (letters, digits and underscores are kept, others become '_').
// Throws UserError naming the file when it cannot be written.
// `textures`: the optional textures (normal.png through a normalmap node in tangent space as the
// shader's normal; coat.png as its coat).
void WriteMaterialX(const std::string& dir, const std::string& name, const PbrTextureSet& textures);

}  // namespace acq
