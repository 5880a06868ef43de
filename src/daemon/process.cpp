#include "daemon/process.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "acq/correspondence_source.h"
#include "acq/hdr.h"
#include "acq/map_render.h"
#include "brdf/basis_file.h"
#include "calib/correspondence.h"
#include "calib/synthetic_board.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/seconds_since.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"
#include "sim/sim_gige_camera.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

ArmAngles ParseArms(const std::string& degrees, const std::string& where) {
  std::istringstream in(degrees);
  double a[4];
  for (double& v : a)
    if (!(in >> v)) throw UserError(where, "no arm angles recorded with the frame");
  return {DegToRad(a[0]), DegToRad(a[1]), DegToRad(a[2]), DegToRad(a[3])};
}

std::string PoseName(const std::string& step, int pose) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%03d", step.c_str(), pose);
  return name;
}

// One pose of a step: its merged HDR image and where the gantry measured the arms.
struct PoseHdr {
  HdrImage hdr;
  ArmAngles arms;
  std::string direction;
};

// Merges every pose of `step` and writes hdr/<step>_NNN.exr.
std::map<int, PoseHdr> MergeStep(const std::string& step, SessionCatalog& catalog,
                                 ProcessReport* report) {
  const auto start = SteadyClock::now();
  const std::string dir = catalog.directory();
  std::map<int, std::vector<CatalogFrame>> by_pose;
  for (const CatalogFrame& f : catalog.Frames())
    if (f.step == step) by_pose[f.pose].push_back(f);
  std::map<int, PoseHdr> merged;
  for (const auto& [pose, frames] : by_pose) {
    std::vector<Frame> bracket;
    std::map<std::string, std::string> attributes;
    for (const CatalogFrame& f : frames)
      bracket.push_back(ReadFrameExr(dir + "/" + f.path, &attributes));
    PoseHdr& p = merged[pose];
    p.hdr = MergeBracket(bracket, {});
    p.arms = ParseArms(attributes["arms_measured_deg"], frames.front().path);
    p.direction = attributes["direction"];
    FloatPlanes file;
    file.width = p.hdr.width;
    file.height = p.hdr.height;
    file.planes["radiance"] = p.hdr.radiance;
    file.planes["flag"].assign(p.hdr.flag.begin(), p.hdr.flag.end());
    file.attributes["unit"] = "counts per microsecond at 0 dB";
    WriteFloatPlanesExr(dir + "/hdr/" + PoseName(step, pose) + ".exr", file);
  }
  report->hdr_s += SecondsSince(start);
  return merged;
}

// A mono camera: one image for R, G and B.
std::array<ViewImage, 3> Channels(const HdrImage& hdr) {
  std::vector<std::uint8_t> unusable(hdr.flag.size());
  for (std::size_t i = 0; i < unusable.size(); ++i) unusable[i] = hdr.flag[i] != kHdrOk;
  const ViewImage image{hdr.width, hdr.height, hdr.radiance, unusable};
  return {image, image, image};
}

// The views of `step` (with the Spectralon captures of `spectralon_step` where there are any):
// each pose's correspondence map, from the camera pose the kinematics give (process.h).
std::vector<SessionView> ViewsOf(const Plan& plan, const std::string& step,
                                 const std::string& spectralon_step,
                                 const calib::ReferenceView& reference,
                                 const SessionGeometry& geometry, SessionCatalog& catalog,
                                 ProcessReport* report) {
  const std::map<int, PoseHdr> sample = MergeStep(step, catalog, report);
  const std::map<int, PoseHdr> spectralon =
      plan.spectralon ? MergeStep(spectralon_step, catalog, report) : std::map<int, PoseHdr>();
  const auto start = SteadyClock::now();
  std::vector<SessionView> views;
  for (const auto& [pose, p] : sample) {
    const sim::SimView pose_view =
        sim::ViewFromArms(p.arms, plan.camera_distance_mm, plan.light_distance_mm, 1);
    const calib::CalibratedView calibrated{geometry.camera, pose_view.cam_from_sample,
                                           pose_view.light.position_mm};
    SessionView view;
    view.name = p.direction.empty() ? PoseName(step, pose) : p.direction;
    view.correspondence = calib::ComputeCorrespondence(reference, calibrated);
    WriteFloatPlanesExr(catalog.directory() + "/correspondence/" + PoseName(step, pose) + ".exr",
                        view.correspondence);
    view.sample = Channels(p.hdr);
    if (plan.spectralon) {
      const auto s = spectralon.find(pose);
      if (s == spectralon.end())
        throw UserError(catalog.directory(), "no Spectralon capture of " + view.name,
                        "run acqd again with the same plan to capture what is missing");
      view.spectralon = Channels(s->second.hdr);
    }
    view.light_in_sample_mm = pose_view.light.position_mm;
    view.light_intensity = geometry.light_intensity;
    views.push_back(std::move(view));
  }
  report->correspondence_s += SecondsSince(start);
  return views;
}

// The map's prediction beside the capture, one PNG with one exposure for both.
void WriteComparison(const ValidationResult& r, const std::string& path) {
  RgbImage both{2 * r.predicted.width, r.predicted.height,
                std::vector<float>(r.predicted.rgb.size() * 2, 0.0f)};
  for (int y = 0; y < both.height; ++y)
    for (int x = 0; x < r.predicted.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::size_t from = (std::size_t(y) * r.predicted.width + x) * 3 + c;
        both.rgb[(std::size_t(y) * both.width + x) * 3 + c] = r.predicted.rgb[from];
        both.rgb[(std::size_t(y) * both.width + x + r.predicted.width) * 3 + c] =
            r.captured.rgb[from];
      }
  WritePng(both, path);
}

}  // namespace

ProcessReport ProcessSession(const Plan& plan, SessionCatalog& catalog,
                             const SessionGeometry& geometry) {
  ProcessReport report;
  const std::string dir = catalog.directory();
  for (const char* sub : {"hdr", "correspondence", "calibration", "renders"})
    fs::create_directories(fs::path(dir) / sub);
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
  report.sample_points = calib::SamplePoints(reference);

  std::vector<SessionView> views =
      ViewsOf(plan, "sample", "spectralon", reference, geometry, catalog, &report);
  if (views.empty()) throw UserError(dir, "no sample frames to process");

  auto start = SteadyClock::now();
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
  report.reconstruction_s = SecondsSince(start);
  catalog.MarkStepDone("reconstruction");

  if (plan.validation.empty()) return report;
  std::vector<SessionView> checks =
      ViewsOf(plan, "validation", "spectralon_validation", reference, geometry, catalog, &report);
  start = SteadyClock::now();
  const SvbrdfMap map = ReadSvbrdfMap(dir + "/svbrdf.exr");
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const std::string name = checks[i].name;
    const ValidationResult r =
        CompareWithCapture(map, mapped.View(), std::move(checks[i]), plan.lookup);
    ValidationSummary s{name, r.pixels, r.relative_rms, r.median_relative,
                        "renders/" + PoseName("validation", int(i)) + ".png"};
    WriteComparison(r, dir + "/" + s.render);
    report.validation.push_back(s);
  }
  report.validation_s = SecondsSince(start);
  return report;
}

}  // namespace acq
