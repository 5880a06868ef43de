#include <cstdio>
#include <filesystem>

#include "acq/map_render.h"
#include "brdf/basis_file.h"
#include "brdf/pooled_model.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/geometry_args.h"
#include "cli/map_and_basis.h"
#include "core/angles.h"
#include "core/error.h"

namespace acq::cli {
namespace {

std::vector<std::pair<int, int>> Pixels(const Args& args) {
  std::vector<std::pair<int, int>> out;
  if (!args.Has("pixel"))
    throw UserError("acq render", "missing --pixel X,Y", "repeat --pixel for several");
  // "X,Y" values: All() splits on commas, so pair them up.
  const std::vector<std::string> parts = args.All("pixel");
  if (parts.size() % 2) throw UserError("--pixel", "expected X,Y pairs");
  for (std::size_t i = 0; i < parts.size(); i += 2) {
    try {
      out.emplace_back(std::stoi(parts[i]), std::stoi(parts[i + 1]));
    } catch (const std::exception&) {
      throw UserError("--pixel",
                      "expected integers X,Y, got '" + parts[i] + "," + parts[i + 1] + "'");
    }
  }
  return out;
}

double DegArg(const Args& args, const std::string& name, double fallback) {
  return DegToRad(args.GetDouble(name, fallback, -360, 360));
}

}  // namespace

int RenderQuicklook(const Argv& argv) {
  const Args args("acq render quicklook", argv, {"map", "basis", "o"}, {});
  const MapAndBasis m = OpenMapAndBasis(args);
  const std::string dir = args.Required("o");
  std::filesystem::create_directories(dir);
  std::string names;
  for (const std::string& name : WriteQuickLooks(m.map, m.basis.View(), dir, ""))
    names += (names.empty() ? "" : ",") + name;
  std::printf("wrote %s/{%s}.png\n", dir.c_str(), names.c_str());
  return 0;
}

int RenderView(const Argv& argv) {
  std::set<std::string> valued = {"map", "basis", "o", "exposure"};
  valued.insert(kGeometryOptions.begin(), kGeometryOptions.end());
  valued.insert(kArmOptions.begin(), kArmOptions.end());
  const Args args("acq render view", argv, valued, {});
  // Every option checked before any file is read.
  const ArmAngles arms = ArmsFrom(args);
  NearFieldGeometry g = GeometriesFrom(args)[0];
  const double exposure = args.GetDouble("exposure", 0, 0, 1e12);
  const MapAndBasis m = OpenMapAndBasis(args);
  const RgbImage img = RenderView(m.map, m.basis.View(), arms, g, MapRowLookup(m.map));
  const std::string out = args.Required("o");
  if (out.size() > 4 && out.compare(out.size() - 4, 4, ".exr") == 0) {
    WriteRgbExr(img, out);  // linear, for comparisons (the Mitsuba export's test)
  } else {
    WritePng(img, out, exposure);
  }
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

int RenderSpheres(const Argv& argv) {
  const Args args(
      "acq render spheres", argv,
      {"map", "basis", "o", "pixel", "size", "light-theta-deg", "light-phi-deg", "exposure"}, {});
  // Every option checked before any file is read.
  const double t = DegArg(args, "light-theta-deg", 45), p = DegArg(args, "light-phi-deg", 135);
  const Eigen::Vector3d light(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
  const int size = args.GetInt("size", 256, 8, 8192);
  const double exposure = args.GetDouble("exposure", 0, 0, 1e12);
  const MapAndBasis m = OpenMapAndBasis(args);
  const RgbImage img =
      RenderSpheres(m.map, m.basis.View(), Pixels(args), light, size, MapRowLookup(m.map));
  WritePng(img, args.Required("o"), exposure);
  std::printf("wrote %s\n", args.Get("o").c_str());
  return 0;
}

int RenderExport(const Argv& argv) {
  const Args args("acq render export", argv, {"map", "basis", "o", "pixel"}, {});
  const MapAndBasis m = OpenMapAndBasis(args);
  const auto pixels = Pixels(args);
  if (pixels.size() != 1) throw UserError("--pixel", "export one pixel at a time");
  WriteMerlBinary(PixelAsMerl(m.map, m.basis.View(), pixels[0].first, pixels[0].second),
                  args.Required("o"));
  std::printf("wrote %s (MERL .binary of pixel %d,%d)\n", args.Get("o").c_str(), pixels[0].first,
              pixels[0].second);
  return 0;
}

}  // namespace acq::cli
