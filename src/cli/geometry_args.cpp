#include "cli/geometry_args.h"

#include <cmath>

#include "core/angles.h"
#include "core/error.h"

namespace acq::cli {

ArmAngles ArmsFrom(const Args& args) {
  auto deg = [&](const char* name, double fallback) {
    return DegToRad(args.GetDouble(name, fallback, -360, 360));
  };
  return {deg("light-theta-deg", 30), deg("light-phi-deg", 0), deg("camera-theta-deg", 0),
          deg("camera-phi-deg", 0)};
}

DirectionConstraints ConstraintsFrom(const Args& args) {
  DirectionConstraints c;
  c.enabled = !args.Has("unconstrained");
  c.max_camera_zenith =
      DegToRad(args.GetDouble("max-camera-zenith-deg", RadToDeg(c.max_camera_zenith)));
  c.max_light_zenith =
      DegToRad(args.GetDouble("max-light-zenith-deg", RadToDeg(c.max_light_zenith)));
  c.min_separation = DegToRad(args.GetDouble("min-separation-deg", RadToDeg(c.min_separation)));
  c.Check();
  return c;
}

std::vector<NearFieldGeometry> GeometriesFrom(const Args& args) {
  NearFieldGeometry base;
  base.camera_distance_mm = args.GetDouble("camera-distance-mm", base.camera_distance_mm);
  base.light_distance_mm = args.GetDouble("light-distance-mm", base.light_distance_mm);
  if (!(base.camera_distance_mm > 0) || !(base.light_distance_mm > 0))
    throw UserError("--camera-distance-mm / --light-distance-mm", "distances must be positive");
  if (args.Has("sample-size-mm") && args.Has("fov-deg"))
    throw UserError("--sample-size-mm", "give either --sample-size-mm or --fov-deg, not both");
  if (args.Has("sample-size-mm")) {
    base.sample_size_mm = args.GetDouble("sample-size-mm", 0);
    if (!(base.sample_size_mm >= 0)) throw UserError("--sample-size-mm", "must be >= 0");
    return {base};
  }
  std::vector<NearFieldGeometry> out;
  const std::vector<std::string> fovs =
      args.Has("fov-deg") ? args.All("fov-deg") : std::vector<std::string>{"0"};
  for (const std::string& f : fovs) {
    double fov = 0;
    try {
      fov = std::stod(f);
    } catch (const std::exception&) {
      throw UserError("--fov-deg", "expected numbers (degrees), got '" + f + "'");
    }
    if (!(fov >= 0 && fov < 90)) throw UserError("--fov-deg", "must be in [0, 90) degrees");
    NearFieldGeometry g = base;
    g.sample_size_mm = NearFieldGeometry::SampleSizeForFov(DegToRad(fov), g.camera_distance_mm);
    out.push_back(g);
  }
  return out;
}

double FovDeg(const NearFieldGeometry& g) {
  return RadToDeg(2 * std::atan(g.sample_size_mm / (2 * g.camera_distance_mm)));
}

}  // namespace acq::cli
