#include "export/gltf_writer.h"

#include <array>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/error.h"
#include "export/pbr_textures.h"

namespace acq {
namespace {

// glTF's dielectric F0 at its default ior 1.5: ((1.5 - 1) / (1.5 + 1))^2.
constexpr double kGltfDielectricF0 = 0.04;

// The quad's interleaved-free buffer: positions, normals, UVs (float), 6 indices (u16), then
// tangents (float).
struct Quad {
  std::array<float, 12> positions;
  std::array<float, 12> normals;
  std::array<float, 8> uvs;
  // +X, handedness +1: the bitangent normal x tangent = -Z is the sample's +y, the textures' up
  // (given, so that the normal map does not depend on a renderer's generated tangents).
  std::array<float, 16> tangents{1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
  std::array<std::uint16_t, 6> indices{0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +Y
};

Quad MakeQuad(double width_m, double height_m) {
  Quad q;
  // Corners by map column and row (x right, r down the rows). The map's rows run towards the
  // sample's -y (the reference camera looks straight down with its image x along the sample's
  // x: calib::CamFromSampleLookingAtCentre), so the sample's x -> glTF X, its y -> glTF -Z (a
  // row r -> +Z) and its normal -> glTF +Y: seen from above, the quad shows the sample as the
  // camera did, not mirrored. Blender's import showed the mirror image when rows went to -Z.
  const double xs[4] = {-0.5, 0.5, 0.5, -0.5}, rs[4] = {-0.5, -0.5, 0.5, 0.5};
  for (int i = 0; i < 4; ++i) {
    const double x = xs[i] * width_m, r = rs[i] * height_m;
    q.positions[3 * i] = float(x);
    q.positions[3 * i + 1] = 0;
    q.positions[3 * i + 2] = float(r);
    q.normals[3 * i] = 0, q.normals[3 * i + 1] = 1, q.normals[3 * i + 2] = 0;
    q.uvs[2 * i] = float(xs[i] + 0.5);
    q.uvs[2 * i + 1] = float(rs[i] + 0.5);  // glTF's v runs down the image, as the rows do
  }
  return q;
}

}  // namespace

void WriteGltf(const std::string& dir, double width_mm, double height_mm, const std::string& name,
               const PbrTextureSet& textures) {
  using nlohmann::json;
  const Quad q = MakeQuad(width_mm / 1000, height_mm / 1000);
  const std::size_t pos = 0, nrm = sizeof(q.positions), uv = nrm + sizeof(q.normals);
  const std::size_t idx = uv + sizeof(q.uvs), tan = idx + sizeof(q.indices);
  const std::size_t total = tan + sizeof(q.tangents);
  {
    std::ofstream bin(dir + "/" + kGltfBuffer, std::ios::binary);
    bin.write(reinterpret_cast<const char*>(q.positions.data()), sizeof(q.positions));
    bin.write(reinterpret_cast<const char*>(q.normals.data()), sizeof(q.normals));
    bin.write(reinterpret_cast<const char*>(q.uvs.data()), sizeof(q.uvs));
    bin.write(reinterpret_cast<const char*>(q.indices.data()), sizeof(q.indices));
    bin.write(reinterpret_cast<const char*>(q.tangents.data()), sizeof(q.tangents));
    if (!bin) throw UserError(dir + "/" + kGltfBuffer, "could not be written", "check the folder");
  }
  const float hx = float(width_mm / 2000), hz = float(height_mm / 2000);
  json gltf;
  gltf["asset"] = {{"version", "2.0"}, {"generator", "acq export pbr"}};
  gltf["extensionsUsed"] = json::array({"KHR_materials_specular"});
  if (textures.coat) gltf["extensionsUsed"].push_back("KHR_materials_clearcoat");
  gltf["scene"] = 0;
  gltf["scenes"] = json::array({{{"name", name}, {"nodes", json::array({0})}}});
  gltf["nodes"] = json::array({{{"name", name}, {"mesh", 0}}});
  json primitive = {
      {"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}, {"TANGENT", 4}}},
      {"indices", 3},
      {"material", 0}};
  gltf["meshes"] = json::array({{{"name", name}, {"primitives", json::array({primitive})}}});
  gltf["buffers"] = json::array({{{"uri", kGltfBuffer}, {"byteLength", total}}});
  auto view = [](std::size_t offset, std::size_t bytes, int target) {
    return json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}};
  };
  constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
  gltf["bufferViews"] = json::array(
      {view(pos, sizeof(q.positions), kArrayBuffer), view(nrm, sizeof(q.normals), kArrayBuffer),
       view(uv, sizeof(q.uvs), kArrayBuffer), view(idx, sizeof(q.indices), kElementArrayBuffer),
       view(tan, sizeof(q.tangents), kArrayBuffer)});
  constexpr int kFloat = 5126, kUnsignedShort = 5123;
  auto accessor = [](int view, int type, int count, const char* kind) {
    return json{{"bufferView", view}, {"componentType", type}, {"count", count}, {"type", kind}};
  };
  json position = accessor(0, kFloat, 4, "VEC3");
  position["min"] = json::array({-hx, 0.0f, -hz});
  position["max"] = json::array({hx, 0.0f, hz});
  gltf["accessors"] =
      json::array({position, accessor(1, kFloat, 4, "VEC3"), accessor(2, kFloat, 4, "VEC2"),
                   accessor(3, kUnsignedShort, 6, "SCALAR"), accessor(4, kFloat, 4, "VEC4")});
  // One image and one texture per file, each texture's index its image's.
  gltf["images"] = json::array();
  gltf["textures"] = json::array();
  auto texture = [&gltf](const char* file) {
    const int index = int(gltf["images"].size());
    gltf["images"].push_back({{"uri", file}});
    gltf["textures"].push_back({{"sampler", 0}, {"source", index}});
    return json{{"index", index}};
  };
  // Nearest: one texel is one measured pixel, not to be blurred into its neighbours.
  constexpr int kNearest = 9728, kClampToEdge = 33071;
  gltf["samplers"] = json::array({{{"magFilter", kNearest},
                                   {"minFilter", kNearest},
                                   {"wrapS", kClampToEdge},
                                   {"wrapT", kClampToEdge}}});
  using N = PbrTextureNames;
  const double f = 1 / kGltfDielectricF0;
  json material = {{"name", name},
                   {"pbrMetallicRoughness",
                    {{"baseColorTexture", texture(N::kBaseColor)},
                     {"metallicRoughnessTexture", texture(N::kMetallicRoughness)},
                     {"metallicFactor", 0.0},
                     {"roughnessFactor", 1.0}}}};
  // F0 = specular * min(0.04 * specularColor, 1) and F90 = specular (the spec's dielectric).
  material["extensions"]["KHR_materials_specular"] = {
      {"specularFactor", 1.0},
      {"specularTexture", texture(N::kSpecularWeight)},
      {"specularColorFactor", json::array({f, f, f})},
      {"specularColorTexture", texture(N::kSpecular)}};
  if (textures.coat) {
    const json coat = texture(N::kCoat);
    material["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0},
                                                         {"clearcoatTexture", coat},
                                                         {"clearcoatRoughnessFactor", 1.0},
                                                         {"clearcoatRoughnessTexture", coat}};
  }
  // The map's rows run to +Z and its texture's up is the sample's +y, which the quad's
  // tangent frame (tangent +X, bitangent normal x tangent = -Z) makes the normal map's +Y.
  if (textures.normal_map) material["normalTexture"] = texture(N::kNormal);
  gltf["materials"] = json::array({material});
  const std::string path = dir + "/" + kGltfFile;
  std::ofstream out(path);
  out << gltf.dump(2) << "\n";
  if (!out) throw UserError(path, "could not be written", "check the folder and the free space");
}

}  // namespace acq
