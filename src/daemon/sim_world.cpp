#include "daemon/sim_world.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "acq/map_score.h"
#include "calib/synthetic_board.h"
#include "core/error.h"

namespace acq {
namespace {

constexpr const char* kSimEnvironmentMark = "ACQD_SIM_ENVIRONMENT";

}  // namespace

bool SimEnvironmentReady() {
  return std::getenv(kSimEnvironmentMark) != nullptr && sim::EmulatedUsbGantry::UnderUmockdev();
}

std::string ReexecForSim(int argc, char** argv) {
  if (std::getenv(kSimEnvironmentMark))
    return "already re-executed, yet umockdev's preload library is not active";
  setenv(kSimEnvironmentMark, "1", 1);
  // unshare -rn: a user and network namespace (no root needed where unprivileged user
  // namespaces are allowed, Debian 12's default); then lo up with 127.0.0.2, and the preload.
  std::vector<char*> args;
  std::string script =
      "ip link set lo up && ip addr add 127.0.0.2/8 dev lo && "
      "exec env LD_PRELOAD=libumockdev-preload.so.0${LD_PRELOAD:+:$LD_PRELOAD} \"$@\"";
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  args.push_back(const_cast<char*>("unshare"));
  args.push_back(const_cast<char*>("-rn"));
  args.push_back(const_cast<char*>("sh"));
  args.push_back(const_cast<char*>("-c"));
  args.push_back(script.data());
  args.push_back(const_cast<char*>("acqd-sim"));
  args.push_back(const_cast<char*>(self.c_str()));
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execvp("unshare", args.data());
  return "cannot run unshare (util-linux) to make the simulated instrument's network namespace";
}

SimWorld::SimWorld(const Plan& plan) {
  for (const std::string& path : plan.sim_materials) networks_.push_back(NeuralBrdf::Load(path));
  scene_.kind = sim::RenderScene::Kind::kCard;
  scene_.sample_size_mm = plan.sample_width_mm;
  // The card's layout at 0.1 mm per label cell, a few times finer than a camera pixel.
  const int cells = std::max(16, int(plan.sample_width_mm * 10));
  scene_.card =
      sim::MakeCardLayout(cells, cells, plan.sample_width_mm, int(networks_.size()), plan.sim_seed);
  for (std::size_t i = 0; i < networks_.size(); ++i) {
    scene_.materials.push_back({&networks_[i], nullptr});
    scene_.material_names.push_back(std::filesystem::path(plan.sim_materials[i]).stem().string());
  }
  // A pinhole camera whose 320 x 320 image holds the sample with a margin at the arm's distance:
  // small frames keep a simulated session quick; the lens model comes from calibration for real.
  const double f = 0.8 * 320 * plan.camera_distance_mm / plan.sample_width_mm;
  model_ = calib::CameraModel("LENSMODEL_PINHOLE", {f, f, 159.5, 159.5}, 320, 320);
  sim::FirmwareOptions firmware;
  firmware.axis = plan.motion.theta;
  firmware.settle_s = plan.motion.settle_s;
  firmware.limits = plan.motion.constraints;
  sim::EmulatedUsbOptions usb;
  usb.vendor_id = plan.usb.vendor_id;
  usb.product_id = plan.usb.product_id;
  usb.serial = plan.usb.serial.empty() ? "SIM-0001" : plan.usb.serial;
  usb_ = plan.usb;
  usb_.serial = usb.serial;
  usb.time_scale = plan.sim_time_scale;
  gantry_ = std::make_unique<sim::EmulatedUsbGantry>(firmware, usb);
  const double camera_mm = plan.camera_distance_mm, light_mm = plan.light_distance_mm;
  const double intensity = plan.sim_light_intensity;
  sim::SimCameraOptions camera;
  camera.seed = plan.sim_seed;
  sensor_ = camera.sensor;
  light_intensity_ = intensity;
  camera_ = std::make_unique<sim::SimGigECamera>(
      scene_, model_,
      [this, camera_mm, light_mm, intensity] {
        const ArmAngles arms =
            gantry_->WithFirmware([](sim::SimGantryFirmware& f) { return f.Measured(); });
        return sim::ViewFromArms(arms, camera_mm, light_mm, intensity);
      },
      camera);
}

double SimWorld::LightIntensityInCounts(PixelFormat format) const {
  return light_intensity_ * sensor_.CountsPerRadianceUs(MaxValue(format));
}

void SimWorld::Place(const std::string& item) {
  sim::RenderScene scene = scene_;
  if (item == "spectralon")
    scene.kind = sim::RenderScene::Kind::kSpectralon;
  else if (item != "sample")
    throw UserError("simulated world", "cannot place '" + item + "'");
  camera_->SetScene(std::move(scene));
}

std::vector<int> SimWorld::LabelsAt(const std::vector<Eigen::Vector3d>& points) const {
  const sim::SyntheticSvbrdf& card = scene_.card;
  const double size = scene_.sample_size_mm;
  std::vector<int> labels;
  labels.reserve(points.size());
  for (const Eigen::Vector3d& p : points) {
    // The renderer's rule (sim/sample_renderer.cpp): the label cell the point falls in.
    const int x = int(std::floor((p.x() / size + 0.5) * card.width));
    const int y = int(std::floor((p.y() / size + 0.5) * card.height));
    const bool on = std::isfinite(p.x()) && x >= 0 && y >= 0 && x < card.width && y < card.height;
    labels.push_back(on ? int(card.label[std::size_t(y) * card.width + x]) : -1);
  }
  return labels;
}

std::vector<MerlBrdf> SimWorld::TruthTables() const {
  std::vector<MerlBrdf> tables;
  for (const NeuralBrdf& n : networks_) tables.push_back(LuminanceOf(n.Tabulate()));
  return tables;
}

void SimWorld::WriteGroundTruth(const std::string& dir) const {
  sim::WriteGroundTruth(dir, scene_, model_);
}

}  // namespace acq
