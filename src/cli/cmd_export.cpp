// acq export pbr | mitsuba: the map in files other renderers read (src/export, docs/export.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "acq/map_render.h"
#include "acq/pbr_maps.h"
#include "acq/validation.h"
#include "brdf/evaluation.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/geometry_args.h"
#include "cli/map_and_basis.h"
#include "core/error.h"
#include "export/gltf_writer.h"
#include "export/materialx_writer.h"
#include "export/mitsuba_export.h"
#include "export/pbr_textures.h"
#include "io/float_planes_exr.h"
#include "sim/ground_truth.h"

namespace acq::cli {
namespace {

namespace fs = std::filesystem;

// The output folder: made when missing, refused when it holds anything (an export never mixes
// with or overwrites other files).
void PrepareOutput(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw UserError("-o " + dir, "exists and is not a folder", "give a new folder");
  if (fs::exists(dir) && !fs::is_empty(dir, ec))
    throw UserError("-o " + dir, "the folder exists and is not empty",
                    "give a new or empty folder (an export never mixes with other files)");
  fs::create_directories(dir, ec);
  if (ec) throw UserError("-o " + dir, "could not be made: " + ec.message(), "check the path");
}

double MedianOf(const std::vector<double>& v) {
  return v.empty() ? 0 : Median(v);
}

// Pixels per class (a material of the truth, a group of a pooled map): the fit's median error.
nlohmann::json ErrorByClass(const PbrMaps& maps, const std::vector<int>& label,
                            const std::vector<std::string>& names) {
  std::map<int, std::vector<double>> errors;
  for (std::size_t p = 0; p < maps.Pixels(); ++p)
    if (maps.valid[p] && label[p] >= 0) errors[label[p]].push_back(maps.log_rmse[p]);
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [c, e] : errors)
    out.push_back({{"name", c < int(names.size()) ? names[c] : "group " + std::to_string(c)},
                   {"pixels", e.size()},
                   {"median_log_rmse", MedianOf(e)}});
  return out;
}

// The session's true material per map pixel (ground_truth/error.exr's label plane), when it
// is a simulated session scored with one; otherwise empty.
std::vector<int> TruthLabels(const std::string& session, const PbrMaps& maps,
                             std::vector<std::string>* names) {
  const std::string path = session + "/ground_truth/error.exr";
  if (!fs::exists(path)) return {};
  const FloatPlanes error = ReadFloatPlanesExr(path);
  if (!error.planes.count("label") || error.width != maps.width || error.height != maps.height)
    return {};
  *names = sim::ReadGroundTruth(session + "/ground_truth").material_names;
  std::vector<int> label;
  for (float v : error.planes.at("label")) label.push_back(int(std::lround(v)));
  return label;
}

// The validation views' data a session kept (renders/validation_NNN.exr), sorted; refused
// when there is none.
std::vector<std::string> ValidationFiles(const std::string& session) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(session + "/renders", ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("validation_", 0) == 0 && e.path().extension() == ".exr")
      files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw UserError("--session " + session,
                    "holds no validation view data (renders/validation_NNN.exr)",
                    "process it again with this version: acq session process " + session +
                        " --from reconstruction -o NEW");
  return files;
}

// Each validation view the session kept, the map's and the fitted maps' prediction against it;
// with the truth's labels (a simulated session), also per true material.
nlohmann::json CompareOnValidationViews(const std::vector<std::string>& files, const SvbrdfMap& map,
                                        const BasisView& basis, const PbrMaps& maps,
                                        const std::vector<int>& truth,
                                        const std::vector<std::string>& names) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& f : files) {
    const ValidationData data = ReadValidationData(f);
    if (data.width != map.info.width || data.height != map.info.height)
      throw UserError(f, "is not of this map's size", "give the map of the same session");
    const ValidationResult measured = Compare(data, MapPixelBrdf(map, basis, MapRowLookup(map)));
    const ValidationResult fitted = Compare(data, PbrPixelBrdf(maps));
    nlohmann::json view = {
        {"view", data.name},
        {"pixels", measured.pixels},
        {"map_relative_rms", measured.relative_rms},
        {"fitted_relative_rms", fitted.relative_rms},
        {"ratio", measured.relative_rms > 0 ? fitted.relative_rms / measured.relative_rms : 0.0},
        {"map_median_delta_e2000", measured.median_delta_e2000},
        {"fitted_median_delta_e2000", fitted.median_delta_e2000}};
    if (truth.size() == std::size_t(data.width) * std::size_t(data.height)) {
      const std::vector<double> a = RelativeRmsByLabel(measured, truth, names.size()),
                                b = RelativeRmsByLabel(fitted, truth, names.size());
      for (std::size_t m = 0; m < names.size(); ++m)
        view["by_material"].push_back(
            {{"name", names[m]}, {"map_relative_rms", a[m]}, {"fitted_relative_rms", b[m]}});
    }
    out.push_back(view);
  }
  return out;
}

std::string MaterialName(const std::string& map_path) {
  std::string stem = fs::path(map_path).stem().string();
  return stem.empty() ? "svbrdf" : stem;
}

}  // namespace

int ExportPbr(const Argv& argv) {
  const Args args("acq export pbr", argv,
                  {"map", "basis", "o", "session", "name", "roughness-steps", "max-iterations",
                   "max-zenith-deg", "model"},
                  {"quiet"});
  PbrFitOptions options;
  if (args.Has("model")) options.model = ParsePbrModel(args.Get("model"), "--model");
  options.roughness_steps = args.GetInt("roughness-steps", options.roughness_steps);
  options.max_iterations = args.GetInt("max-iterations", options.max_iterations);
  options.max_zenith_deg = args.GetDouble("max-zenith-deg", options.max_zenith_deg);
  options.Check();
  const std::string dir = args.Required("o");
  const std::string session = args.Get("session");
  if (!session.empty() && !fs::is_directory(session))
    throw UserError("--session " + session, "is not a folder", "give an acqd session's folder");
  const std::vector<std::string> validation =
      session.empty() ? std::vector<std::string>() : ValidationFiles(session);
  const MapAndBasis m = OpenMapAndBasis(args);
  PrepareOutput(dir);
  const PbrMaps maps = FitPbrMaps(m.map, m.basis.View(), options, !args.Has("quiet"));
  PbrTextureSet textures = WritePbrTextures(maps, dir);
  const std::string name = args.Get("name", MaterialName(args.Get("map")));
  const double width_mm = m.map.info.width * m.map.info.pixel_size_mm;
  const double height_mm = m.map.info.height * m.map.info.pixel_size_mm;
  // The normals the reconstruction estimated (issue 19), as the renderers' normal maps.
  textures.normal_map = HasEstimatedNormals(m.map);
  if (textures.normal_map) WriteNormalPng(m.map, dir + "/" + PbrTextureNames::kNormal);
  WriteGltf(dir, width_mm, height_mm, name, textures);
  WriteMaterialX(dir, name, textures);

  std::vector<double> valid_errors, f0, specular;
  long converged = 0, coated = 0;
  for (std::size_t p = 0; p < maps.Pixels(); ++p) {
    if (maps.valid[p]) {
      const PbrParameters& q = maps.parameters[p];
      valid_errors.push_back(maps.log_rmse[p]);
      f0.push_back(q.specular * *std::max_element(q.f0.begin(), q.f0.end()));
      specular.push_back(q.specular);
      coated += q.coat > 0;
    }
    converged += maps.converged[p];
  }
  nlohmann::json report = {{"map", args.Get("map")},
                           {"model", PbrModelName(options.model)},
                           {"max_zenith_deg", options.max_zenith_deg},
                           {"pixels", maps.Pixels()},
                           {"valid_pixels", valid_errors.size()},
                           {"not_converged", long(maps.Pixels()) - converged},
                           {"median_log_rmse", MedianOf(valid_errors)},
                           // For renderers with one F0 for a material (Mitsuba's principled):
                           // the reflectance at normal incidence, F90 (specular) x F0 / F90.
                           {"median_f0", MedianOf(f0)},
                           {"median_specular_weight", MedianOf(specular)},
                           {"coated_pixels", coated},
                           {"fit_seconds", maps.seconds}};
  std::vector<int> group;
  for (int y = 0; y < m.map.info.height; ++y)
    for (int x = 0; x < m.map.info.width; ++x)
      group.push_back(int(std::lround(m.map.Plane("group", x, y))));
  if (*std::max_element(group.begin(), group.end()) >= 0)
    report["by_group"] = ErrorByClass(maps, group, {});
  if (!session.empty()) {
    std::vector<std::string> names;
    const std::vector<int> truth = TruthLabels(session, maps, &names);
    if (!truth.empty()) report["by_material"] = ErrorByClass(maps, truth, names);
    report["validation"] =
        CompareOnValidationViews(validation, m.map, m.basis.View(), maps, truth, names);
  }
  std::ofstream(dir + "/fit.json") << report.dump(2) << "\n";

  std::printf(
      "fitted %zu pixels in %.1f s (model %s): median log-space error %.4f over %zu valid "
      "pixels, %ld with a coat, %ld not converged\n",
      maps.Pixels(), maps.seconds, PbrModelName(options.model), MedianOf(valid_errors),
      valid_errors.size(), coated, long(maps.Pixels()) - converged);
  for (const char* key : {"by_material", "by_group"})
    if (report.contains(key))
      for (const auto& c : report[key])
        std::printf("  %-28s %8ld pixels, median fit error %.4f\n",
                    c["name"].get<std::string>().c_str(), c["pixels"].get<long>(),
                    c["median_log_rmse"].get<double>());
  if (report.contains("validation"))
    for (const auto& v : report["validation"]) {
      std::printf("  validation %-24s relative RMS: map %.4f, fitted %.4f (%.2fx)\n",
                  v["view"].get<std::string>().c_str(), v["map_relative_rms"].get<double>(),
                  v["fitted_relative_rms"].get<double>(), v["ratio"].get<double>());
      if (v.contains("by_material"))
        for (const auto& c : v["by_material"])
          std::printf("    %-26s map %.4f, fitted %.4f\n", c["name"].get<std::string>().c_str(),
                      c["map_relative_rms"].get<double>(), c["fitted_relative_rms"].get<double>());
    }
  using N = PbrTextureNames;
  std::string written = std::string(kGltfFile) + "," + kGltfBuffer + "," + kMaterialXFile;
  for (const char* f : {N::kBaseColor, N::kMetallicRoughness, N::kSpecular, N::kSpecularWeight,
                        N::kRoughness, N::kFitError, N::kFitErrorPng})
    written += std::string(",") + f;
  if (textures.coat) written += std::string(",") + N::kCoat;
  if (textures.normal_map) written += std::string(",") + N::kNormal;
  std::printf("wrote %s/{%s,fit.json}\n", dir.c_str(), written.c_str());
  return 0;
}

int ExportMitsuba(const Argv& argv) {
  std::set<std::string> valued = {"map", "basis", "o", "camera-distance-mm", "light-distance-mm"};
  valued.insert(kArmOptions.begin(), kArmOptions.end());
  const Args args("acq export mitsuba", argv, valued, {});
  MitsubaExport options;
  options.arms = ArmsFrom(args);
  options.camera_distance_mm = args.GetDouble("camera-distance-mm", 1000, 10, 1e6);
  options.light_distance_mm = args.GetDouble("light-distance-mm", 1000, 10, 1e6);
  const std::string dir = args.Required("o");
  const MapAndBasis m = OpenMapAndBasis(args);
  options.basis_path = m.basis_path;
  PrepareOutput(dir);
  WriteMitsubaExport(m.map, options, dir);
  std::printf(
      "wrote %s/{scene.json,coefficients.bin,acq_svbrdf.py,render.py}\n"
      "render it: .venv/bin/python %s/render.py (docs/export.md)\n",
      dir.c_str(), dir.c_str());
  return 0;
}

}  // namespace acq::cli
