#include "hw/replay_gantry.h"

#include <cmath>

#include "core/angles.h"
#include "core/error.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"

namespace acq {
namespace {

// Commanded angles are written with 3 decimals of a degree: poses within 0.002 deg are one.
bool SamePose(const ArmAngles& a, const ArmAngles& b) {
  const double tolerance = DegToRad(0.002);
  auto near = [&](double x, double y) {
    return std::abs(std::remainder(x - y, 2 * M_PI)) <= tolerance;
  };
  return near(a.light_theta, b.light_theta) && near(a.light_phi, b.light_phi) &&
         near(a.camera_theta, b.camera_theta) && near(a.camera_phi, b.camera_phi);
}

}  // namespace

ReplayGantry::ReplayGantry(const std::vector<std::string>& frame_files) {
  for (const std::string& path : frame_files) {
    const FloatPlanes header = ReadFloatPlanesExr(path, /*read_pixels=*/false);
    auto attribute = [&](const char* name) {
      const auto it = header.attributes.find(name);
      if (it == header.attributes.end())
        throw UserError(path, std::string("no '") + name + "' recorded with the frame",
                        "replay a session recorded by acqd");
      return ParseArmAnglesAttribute(it->second, path);
    };
    poses_.push_back({attribute("arms_commanded_deg"), attribute("arms_measured_deg")});
  }
  status_.homed_mask = 0x0F;
}

void ReplayGantry::Home() {
  status_.commanded = status_.measured = ArmAngles{};
  status_.homed_mask = 0x0F;
}

void ReplayGantry::MoveTo(const ArmAngles& target) {
  // The first match from where the recording is: the same pose visited twice (the sample's
  // pass, the Spectralon's) reports what was measured on that visit.
  for (std::size_t k = 0; k < poses_.size(); ++k) {
    const std::size_t i = (next_ + k) % poses_.size();
    if (!SamePose(poses_[i].commanded, target)) continue;
    status_.commanded = target;
    status_.measured = poses_[i].measured;
    next_ = i + 1;
    return;
  }
  throw UserError("replay gantry",
                  "the recorded session was never at " + ArmAnglesAttribute(target) +
                      " deg (light theta, phi, camera theta, phi)",
                  "replay the session with the plan it was recorded with");
}

}  // namespace acq
