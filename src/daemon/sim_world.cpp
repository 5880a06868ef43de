#include "daemon/sim_world.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "acq/map_score.h"
#include "calib/extrinsics.h"
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
  scene_.board = calib::BoardSpec{plan.board_width_n, plan.board_height_n, plan.board_spacing_mm};
  PlaceHeldBoards(plan);
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

// The operator's board poses for the intrinsics: spread over the view of the camera straight
// above the sample (where the sequencer holds it for these captures), tilted up to 35 degrees
// towards any side, within 5% of the arm's distance.
void SimWorld::PlaceHeldBoards(const Plan& plan) {
  if (plan.intrinsics_captures == 0) return;
  calib::BoardPoseSampling sampling;
  sampling.min_distance_mm = 0.95 * plan.camera_distance_mm;
  sampling.max_distance_mm = 1.05 * plan.camera_distance_mm;
  sampling.max_tilt_deg = 35;
  sampling.seed = plan.sim_seed;
  const std::vector<calib::Pose> cam_from_board =
      calib::SampleBoardPoses(model_, scene_.board, plan.intrinsics_captures, sampling);
  if (int(cam_from_board.size()) < plan.intrinsics_captures) {
    const double view_mm = model_.width() / model_.intrinsics()[0] * plan.camera_distance_mm;
    char why[160];
    std::snprintf(why, sizeof why,
                  "the board (%d x %d corners, %.1f mm squares) does not fit the simulated "
                  "camera's view, %.0f mm across",
                  scene_.board.width_n, scene_.board.height_n, scene_.board.spacing_mm, view_mm);
    throw UserError(plan.path, why, "give calibration.board a smaller spacing_mm or size");
  }
  const calib::Pose sample_from_cam =
      calib::CamFromSampleLookingAtCentre({0, 0, plan.camera_distance_mm}).Inverse();
  // mrcal's board frame to the chessboard's (the sample frame a flat board defines).
  const calib::Pose board_from_chessboard = calib::SampleFromBoard(scene_.board).Inverse();
  for (const calib::Pose& p : cam_from_board)
    held_boards_.push_back(sample_from_cam.Compose(p).Compose(board_from_chessboard));
}

double SimWorld::LightIntensityInCounts(PixelFormat format) const {
  return light_intensity_ * sensor_.CountsPerRadianceUs(MaxValue(format));
}

void SimWorld::Place(const std::string& item) {
  sim::RenderScene scene = scene_;
  const std::string held = std::string(kBoardItem) + "/";
  if (item == "spectralon") {
    scene.kind = sim::RenderScene::Kind::kSpectralon;
  } else if (item == kBoardItem) {
    scene.kind = sim::RenderScene::Kind::kChessboard;  // flat on the sample plane
  } else if (item.rfind(held, 0) == 0) {
    const std::size_t k = std::stoul(item.substr(held.size()));
    if (k < 1 || k > held_boards_.size())
      throw UserError("simulated world", "no board pose " + item.substr(held.size()));
    scene.kind = sim::RenderScene::Kind::kChessboard;
    scene.sample_from_chessboard = held_boards_[k - 1];
  } else if (item != "sample") {
    throw UserError("simulated world", "cannot place '" + item + "'");
  }
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
