#include "export/mitsuba_export.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "acq/map_render.h"
#include "brdf/basis_rows.h"
#include "core/angles.h"
#include "core/error.h"
#include "embedded_mitsuba.h"

namespace acq {
namespace {

void WriteText(const std::string& path, const char* text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw UserError(path, "could not be written", "check the folder and the free space");
}

}  // namespace

void WriteMitsubaExport(const SvbrdfMap& map, const MitsubaExport& options,
                        const std::string& dir) {
  const int w = map.info.width, h = map.info.height, k = map.info.components;
  {
    const std::string path = dir + "/coefficients.bin";
    std::ofstream out(path, std::ios::binary);
    std::vector<float> pixel(3 * std::size_t(k));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t at = std::size_t(y) * w + x;
        for (int j = 0; j < 3 * k; ++j) pixel[j] = map.planes[j][at];
        out.write(reinterpret_cast<const char*>(pixel.data()),
                  std::streamsize(pixel.size() * sizeof(float)));
      }
    if (!out) throw UserError(path, "could not be written", "check the folder and the free space");
  }
  const std::string lookup = RowLookupName(MapRowLookup(map));
  char crc[9];
  std::snprintf(crc, sizeof(crc), "%08x", map.info.basis_crc32);
  const nlohmann::json scene = {{"format", "acq-mitsuba-export 1"},
                                {"width", w},
                                {"height", h},
                                {"components", k},
                                {"pixel_size_mm", map.info.pixel_size_mm},
                                {"lookup", lookup},
                                {"coefficients", "coefficients.bin"},
                                {"basis", std::filesystem::absolute(options.basis_path).string()},
                                {"basis_crc32", crc},
                                {"light",
                                 {{"theta_deg", RadToDeg(options.arms.light_theta)},
                                  {"phi_deg", RadToDeg(options.arms.light_phi)},
                                  {"distance_mm", options.light_distance_mm}}},
                                {"camera",
                                 {{"theta_deg", RadToDeg(options.arms.camera_theta)},
                                  {"phi_deg", RadToDeg(options.arms.camera_phi)},
                                  {"distance_mm", options.camera_distance_mm}}}};
  const std::string json_path = dir + "/scene.json";
  std::ofstream out(json_path);
  out << scene.dump(2) << "\n";
  if (!out) throw UserError(json_path, "could not be written", "check the folder");
  WriteText(dir + "/acq_svbrdf.py", embedded::kMitsubaPlugin);
  WriteText(dir + "/render.py", embedded::kMitsubaRender);
}

}  // namespace acq
