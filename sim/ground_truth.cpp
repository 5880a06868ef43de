#include "sim/ground_truth.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/sample_grid.h"
#include "io/float_planes_exr.h"

namespace acq::sim {
namespace {

// Version 2: the card's grid lies on the sample by core/sample_grid.h (rows to the sample's -y).
// Version 1 (sessions simulated before 2026-12-03) ran its rows to +y: read, its rows are turned
// over so that every stored cell keeps its place on the sample.
constexpr const char* kFormat = "acq-ground-truth-2";
constexpr const char* kFormatRowsUp = "acq-ground-truth-1";

}  // namespace

void WriteGroundTruth(const std::string& dir, const RenderScene& scene,
                      const calib::CameraModel& camera) {
  std::filesystem::create_directories(dir);
  FloatPlanes labels;
  labels.width = scene.card.width;
  labels.height = scene.card.height;
  labels.planes["material"].assign(scene.card.label.begin(), scene.card.label.end());
  // The relief's true normals (sample frame, unit), where the card has relief.
  const char* axes[3] = {"normal.x", "normal.y", "normal.z"};
  for (int a = 0; a < 3 && !scene.card.normal.empty(); ++a)
    for (const Eigen::Vector3f& n : scene.card.normal) labels.planes[axes[a]].push_back(n[a]);
  labels.attributes["acqFormat"] = kFormat;
  std::ostringstream size;
  size.precision(17);  // read back exactly: the label rule divides by it
  size << scene.card.sample_size_mm;
  labels.attributes["sampleSizeMm"] = size.str();
  WriteFloatPlanesExr(dir + "/ground_truth_labels.exr", labels);
  std::ofstream names(dir + "/materials.tsv");
  names << "# index\tname\n";
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    names << i << "\t"
          << (i < scene.material_names.size() ? scene.material_names[i]
                                              : "material" + std::to_string(i))
          << "\n";
  camera.Write(dir + "/camera.cameramodel");
}

GroundTruthFiles ReadGroundTruth(const std::string& dir) {
  const std::string labels_path = dir + "/ground_truth_labels.exr";
  const FloatPlanes labels = ReadFloatPlanesExr(labels_path);
  const auto format = labels.attributes.find("acqFormat");
  const auto size = labels.attributes.find("sampleSizeMm");
  const auto material = labels.planes.find("material");
  const bool known = format != labels.attributes.end() &&
                     (format->second == kFormat || format->second == kFormatRowsUp);
  if (!known || size == labels.attributes.end() || material == labels.planes.end())
    throw UserError(labels_path, "not the simulated card's ground truth (" + std::string(kFormat) +
                                     " with a material plane and sampleSizeMm)");
  GroundTruthFiles truth;
  truth.card.width = labels.width;
  truth.card.height = labels.height;
  truth.card.sample_size_mm = std::atof(size->second.c_str());
  for (float v : material->second) truth.card.label.push_back(std::uint8_t(std::lround(v)));
  const auto nx = labels.planes.find("normal.x"), ny = labels.planes.find("normal.y"),
             nz = labels.planes.find("normal.z");
  if (nx != labels.planes.end() && ny != labels.planes.end() && nz != labels.planes.end())
    for (std::size_t i = 0; i < nx->second.size(); ++i)
      truth.card.normal.push_back(
          Eigen::Vector3f(nx->second[i], ny->second[i], nz->second[i]).normalized());
  if (format->second == kFormatRowsUp) {  // the normals are sample-frame vectors: only moved
    FlipGridRows(&truth.card.label, truth.card.width);
    FlipGridRows(&truth.card.normal, truth.card.width);
  }
  std::ifstream names(dir + "/materials.tsv");
  for (std::string line; std::getline(names, line);) {
    if (line.empty() || line[0] == '#') continue;
    const std::size_t tab = line.find('\t');
    truth.material_names.push_back(tab == std::string::npos ? line : line.substr(tab + 1));
  }
  truth.camera = calib::CameraModel::Read(dir + "/camera.cameramodel");
  return truth;
}

}  // namespace acq::sim
