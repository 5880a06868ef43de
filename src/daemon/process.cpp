#include "daemon/process.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "acq/correspondence_source.h"
#include "acq/hdr.h"
#include "brdf/basis_file.h"
#include "calib/correspondence.h"
#include "calib/synthetic_board.h"
#include "core/angles.h"
#include "core/error.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"
#include "sim/sim_gige_camera.h"

namespace acq {
namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

ArmAngles ParseArms(const std::string& degrees, const std::string& where) {
  std::istringstream in(degrees);
  double a[4];
  for (double& v : a)
    if (!(in >> v)) throw UserError(where, "no arm angles recorded with the frame");
  return {DegToRad(a[0]), DegToRad(a[1]), DegToRad(a[2]), DegToRad(a[3])};
}

}  // namespace

ProcessReport ProcessSample(const Plan& plan, SessionCatalog& catalog,
                            const SessionGeometry& geometry) {
  ProcessReport report;
  const std::string dir = catalog.directory();
  fs::create_directories(fs::path(dir) / "hdr");
  fs::create_directories(fs::path(dir) / "correspondence");
  fs::create_directories(fs::path(dir) / "calibration");
  geometry.camera.Write(dir + "/calibration/camera.cameramodel");

  // The reference view: the camera straight above the sample centre, cropped to the sample.
  calib::ReferenceView reference;
  reference.camera = geometry.camera;
  reference.cam_from_sample = calib::CamFromSampleLookingAtCentre({0, 0, plan.camera_distance_mm});
  report.pixel_size_mm = plan.camera_distance_mm / geometry.camera.intrinsics()[0];
  const int w = geometry.camera.width(), h = geometry.camera.height();
  reference.width = std::min(w, int(plan.sample_width_mm / report.pixel_size_mm));
  reference.height = std::min(h, int(plan.sample_height_mm / report.pixel_size_mm));
  reference.x0 = (w - reference.width) / 2;
  reference.y0 = (h - reference.height) / 2;
  report.reference_width = reference.width;
  report.reference_height = reference.height;

  std::map<int, std::vector<CatalogFrame>> by_pose;
  for (const CatalogFrame& f : catalog.Frames())
    if (f.step == "sample") by_pose[f.pose].push_back(f);
  std::vector<SessionView> views;
  for (const auto& [pose, frames] : by_pose) {
    auto start = Clock::now();
    std::vector<Frame> bracket;
    std::map<std::string, std::string> attributes;
    for (const CatalogFrame& f : frames)
      bracket.push_back(ReadFrameExr(dir + "/" + f.path, &attributes));
    const HdrImage hdr = MergeBracket(bracket, {});
    char name[32];
    std::snprintf(name, sizeof name, "%03d.exr", pose);
    FloatPlanes hdr_file;
    hdr_file.width = hdr.width;
    hdr_file.height = hdr.height;
    hdr_file.planes["radiance"] = hdr.radiance;
    hdr_file.planes["flag"].assign(hdr.flag.begin(), hdr.flag.end());
    hdr_file.attributes["unit"] = "counts per microsecond at 0 dB";
    WriteFloatPlanesExr(dir + "/hdr/" + name, hdr_file);
    report.hdr_s += Since(start);

    start = Clock::now();
    const ArmAngles arms = ParseArms(attributes["arms_measured_deg"], frames.front().path);
    const sim::SimView pose_view =
        sim::ViewFromArms(arms, plan.camera_distance_mm, plan.light_distance_mm, 1);
    const calib::CalibratedView calibrated{geometry.camera, pose_view.cam_from_sample,
                                           pose_view.light.position_mm};
    SessionView view;
    view.name = dir + "/correspondence/" + name;
    view.correspondence = calib::ComputeCorrespondence(reference, calibrated);
    WriteFloatPlanesExr(view.name, view.correspondence);
    std::vector<std::uint8_t> unusable(hdr.flag.size());
    for (std::size_t i = 0; i < unusable.size(); ++i) unusable[i] = hdr.flag[i] != kHdrOk;
    for (ViewImage& channel : view.sample)  // a mono camera: one image for R, G and B
      channel = {hdr.width, hdr.height, hdr.radiance, unusable};
    view.light_in_sample_mm = pose_view.light.position_mm;
    view.light_intensity = geometry.light_intensity;
    views.push_back(std::move(view));
    report.correspondence_s += Since(start);
  }
  if (views.empty()) throw UserError(dir, "no sample frames to process");

  const auto start = Clock::now();
  CorrespondenceSource source(std::move(views), report.pixel_size_mm);
  const MappedBasis mapped = MappedBasis::Open(plan.basis_file);
  ReconstructionOptions options;
  options.solve.components = plan.components;
  options.solve.eta = plan.eta;
  options.solve.lookup = plan.lookup;
  options.solve.row_tile = plan.row_tile;
  options.progress = false;
  SvbrdfMapInfo info;
  info.basis = plan.basis_file;
  info.basis_crc32 = mapped.Checksum();
  info.camera_model = dir + "/calibration/camera.cameramodel";
  report.reconstruction = Reconstruct(mapped.View(), source, options, info, dir + "/svbrdf.exr");
  report.reconstruction_s = Since(start);
  catalog.MarkStepDone("reconstruction");
  return report;
}

}  // namespace acq
