#include "export/materialx_writer.h"

#include <cctype>
#include <fstream>

#include "core/error.h"
#include "export/pbr_textures.h"

namespace acq {
namespace {

// MaterialX names are identifiers: [A-Za-z_][A-Za-z0-9_]*.
std::string Identifier(const std::string& name) {
  std::string id;
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (id.empty() || std::isdigit(static_cast<unsigned char>(id[0]))) id = "m_" + id;
  return id;
}

}  // namespace

void WriteMaterialX(const std::string& dir, const std::string& name,
                    const PbrTextureSet& textures) {
  using N = PbrTextureNames;
  const std::string id = Identifier(name);
  const std::string path = dir + "/" + kMaterialXFile;
  std::ofstream out(path);
  auto extract = [&](const char* node, const char* from, const char* type, int index) {
    out << "    <extract name=\"" << node << "\" type=\"float\">\n"
        << "      <input name=\"in\" type=\"" << type << "\" nodename=\"" << from << "\" />\n"
        << "      <input name=\"index\" type=\"integer\" value=\"" << index << "\" />\n"
        << "    </extract>\n";
  };
  auto binary = [&](const char* op, const char* node, const char* type, const std::string& in1,
                    const std::string& in2, const char* type2 = nullptr) {
    out << "    <" << op << " name=\"" << node << "\" type=\"" << type << "\">\n"
        << "      <input name=\"in1\" type=\"" << type << "\" " << in1 << " />\n"
        << "      <input name=\"in2\" type=\"" << (type2 ? type2 : type) << "\" " << in2 << " />\n"
        << "    </" << op << ">\n";
  };
  // Closest texel, as the glTF's sampler asks: a texel is one pixel's fit. MaterialX's GLSL
  // renderer blends neighbouring texels all the same (measured: a 1-texel checkerboard of two
  // fits rendered 3x brighter than either), which is why the fit gives an unused lobe its
  // counterpart's shape (pbr_model.cpp, GiveUnusedParametersTheirCounterparts).
  auto image = [&](const char* node, const char* type, const char* file, bool srgb) {
    out << "    <image name=\"" << node << "\" type=\"" << type << "\">\n"
        << "      <input name=\"file\" type=\"filename\" value=\"" << file << "\""
        << (srgb ? " colorspace=\"srgb_texture\"" : "") << " />\n"
        << "      <input name=\"filtertype\" type=\"string\" value=\"closest\" />\n"
        << "    </image>\n";
  };
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- Written by acq export pbr: the analytic maps fitted to a measured SVBRDF. -->\n"
      << "<materialx version=\"1.39\" colorspace=\"lin_rec709\">\n"
      << "  <nodegraph name=\"NG_" << id << "\">\n";
  image("basecolor", "color3", N::kBaseColor, true);
  image("metallic_roughness", "vector3", N::kMetallicRoughness, false);
  image("specular", "color3", N::kSpecular, true);
  image("specular_weight", "float", N::kSpecularWeight, false);
  if (textures.coat) {
    image("coat_texture", "vector3", N::kCoat, false);
    extract("coat", "coat_texture", "vector3", 0);
    extract("coat_roughness", "coat_texture", "vector3", 1);
  }
  extract("roughness", "metallic_roughness", "vector3", 1);
  extract("f0_r", "specular", "color3", 0);
  extract("f0_g", "specular", "color3", 1);
  extract("f0_b", "specular", "color3", 2);
  binary("max", "f0_rg", "float", "nodename=\"f0_r\"", "nodename=\"f0_g\"");
  binary("max", "f0_rgb", "float", "nodename=\"f0_rg\"", "nodename=\"f0_b\"");
  // F0 kept in (1e-4, 0.99): the IOR stays finite and the tint defined.
  out << "    <clamp name=\"f0_max\" type=\"float\">\n"
      << "      <input name=\"in\" type=\"float\" nodename=\"f0_rgb\" />\n"
      << "      <input name=\"low\" type=\"float\" value=\"0.0001\" />\n"
      << "      <input name=\"high\" type=\"float\" value=\"0.99\" />\n"
      << "    </clamp>\n";
  binary("divide", "tint", "color3", "nodename=\"specular\"", "nodename=\"f0_max\"", "float");
  out << "    <sqrt name=\"sqrt_f0\" type=\"float\">\n"
      << "      <input name=\"in\" type=\"float\" nodename=\"f0_max\" />\n"
      << "    </sqrt>\n";
  binary("add", "ior_above", "float", "value=\"1.0\"", "nodename=\"sqrt_f0\"");
  binary("subtract", "ior_below", "float", "value=\"1.0\"", "nodename=\"sqrt_f0\"");
  binary("divide", "ior", "float", "nodename=\"ior_above\"", "nodename=\"ior_below\"");
  if (textures.normal_map) {
    image("normal_texture", "vector3", N::kNormal, false);
    out << "    <normalmap name=\"normal\" type=\"vector3\">\n"
        << "      <input name=\"in\" type=\"vector3\" nodename=\"normal_texture\" />\n"
        << "    </normalmap>\n"
        << "    <output name=\"normal_out\" type=\"vector3\" nodename=\"normal\" />\n";
  }
  std::vector<const char*> outputs = {"basecolor", "roughness", "tint", "ior", "specular_weight"};
  if (textures.coat) outputs.insert(outputs.end(), {"coat", "coat_roughness"});
  for (const char* o : outputs) {
    const bool colour = std::string(o) == "basecolor" || std::string(o) == "tint";
    out << "    <output name=\"" << o << "_out\" type=\"" << (colour ? "color3" : "float")
        << "\" nodename=\"" << o << "\" />\n";
  }
  const std::string graph = "NG_" + id;
  out << "  </nodegraph>\n"
      << "  <standard_surface name=\"SR_" << id << "\" type=\"surfaceshader\">\n"
      << "    <input name=\"base\" type=\"float\" value=\"1.0\" />\n"
      << "    <input name=\"base_color\" type=\"color3\" nodegraph=\"" << graph
      << "\" output=\"basecolor_out\" />\n"
      << "    <input name=\"metalness\" type=\"float\" value=\"0.0\" />\n"
      << "    <input name=\"specular\" type=\"float\" nodegraph=\"" << graph
      << "\" output=\"specular_weight_out\" />\n"
      << "    <input name=\"specular_color\" type=\"color3\" nodegraph=\"" << graph
      << "\" output=\"tint_out\" />\n"
      << "    <input name=\"specular_roughness\" type=\"float\" nodegraph=\"" << graph
      << "\" output=\"roughness_out\" />\n"
      << "    <input name=\"specular_IOR\" type=\"float\" nodegraph=\"" << graph
      << "\" output=\"ior_out\" />\n";
  if (textures.coat)
    for (const char* input : {"coat", "coat_roughness"})
      out << "    <input name=\"" << input << "\" type=\"float\" nodegraph=\"" << graph
          << "\" output=\"" << input << "_out\" />\n";
  if (textures.normal_map)
    out << "    <input name=\"normal\" type=\"vector3\" nodegraph=\"" << graph
        << "\" output=\"normal_out\" />\n";
  out << "  </standard_surface>\n"
      << "  <surfacematerial name=\"" << id << "\" type=\"material\">\n"
      << "    <input name=\"surfaceshader\" type=\"surfaceshader\" nodename=\"SR_" << id
      << "\" />\n"
      << "  </surfacematerial>\n"
      << "</materialx>\n";
  if (!out) throw UserError(path, "could not be written", "check the folder and the free space");
}

}  // namespace acq
