#include "session/truth_score.h"

#include "session/sim_instrument.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "acq/validation.h"
#include "brdf/basis_file.h"
#include "brdf/directions.h"
#include "brdf/evaluation.h"
#include "calib/correspondence.h"
#include "core/angles.h"
#include "core/facet_frame.h"
#include "io/float_planes_exr.h"
#include "session/view_correspondence.h"
#include "sim/ground_truth.h"
#include "sim/instrument.h"
#include "sim/sim_gige_camera.h"

namespace acq {
namespace {

// The card's normals over each map pixel's footprint on the sample: a kSub x kSub grid of points
// across the parallelogram its neighbours' points span.
constexpr int kSub = 4;
// The footprints whose normals differ (a relief's edges): per map pixel the index of its kSub^2
// normals in `normals`, -1 where they are one (the pixel's mean normal).
struct FootprintFacets {
  std::vector<int> first;
  std::vector<Eigen::Vector3f> normals;
};
// Each map pixel's mean normal over its footprint, as a normal map at the map's resolution holds
// it (a point sample at the pixel's centre would score the estimate against a normal that only
// part of the pixel shows: the embossing's edges are a pixel or two wide); the facets where they
// differ into `facets`.
std::vector<Eigen::Vector3f> FootprintNormals(const sim::SyntheticSvbrdf& card,
                                              const std::vector<Eigen::Vector3d>& points, int w,
                                              int h, FootprintFacets* facets) {
  std::vector<Eigen::Vector3f> mean(points.size(), Eigen::Vector3f::UnitZ());
  facets->first.assign(points.size(), -1);
  facets->normals.clear();
  auto at = [&](int x, int y) -> Eigen::Vector2d {
    return points[std::size_t(std::clamp(y, 0, h - 1)) * w + std::clamp(x, 0, w - 1)].head<2>();
  };
  std::vector<Eigen::Vector3f> grid(kSub * kSub);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector2d c = at(x, y);
      const Eigen::Vector2d du = (at(x + 1, y) - at(x - 1, y)) / (x > 0 && x < w - 1 ? 2 : 1);
      const Eigen::Vector2d dv = (at(x, y + 1) - at(x, y - 1)) / (y > 0 && y < h - 1 ? 2 : 1);
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      bool one = true;
      for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
          Eigen::Vector3f& n = grid[std::size_t(j * kSub + i)];
          n = card.NormalAt(c + du * ((i + 0.5) / kSub - 0.5) + dv * ((j + 0.5) / kSub - 0.5));
          sum += n;
          one = one && n == grid[0];
        }
      const std::size_t p = std::size_t(y) * w + x;
      mean[p] = sum.normalized();
      if (one) continue;
      facets->first[p] = int(facets->normals.size());
      facets->normals.insert(facets->normals.end(), grid.begin(), grid.end());
    }
  return mean;
}

// The card's true materials (as the camera records them: linear Rec. 709, or luminance for a
// mono camera), and the true material's label at each map pixel.
struct TruthAtPixels {
  std::vector<MerlBrdf> materials;
  std::vector<int> labels;               // per map pixel, -1 off the card
  std::vector<Eigen::Vector3f> normals;  // per map pixel; empty without relief or a search
  FootprintFacets relief;                // empty without relief
};
TruthAtPixels TruthOfMap(const Plan& plan, const sim::GroundTruthFiles& truth_files,
                         const ProcessReport& process) {
  TruthAtPixels t;
  const bool colour = CfaOf(plan.camera.settings.pixel_format) != Cfa::kNone;
  t.materials = sim::TruthTables(InstrumentOptionsOf(plan), colour);
  // Where each map pixel lies on the sample: computed here, for scoring only (2 s of mrcal's
  // unprojection at 2048 x 2048, not the processing's to spend).
  const calib::ReferenceView reference = ReferenceViewOf(plan, process.calibration.camera);
  const std::vector<Eigen::Vector3d> points = calib::SamplePoints(reference);
  for (const Eigen::Vector3d& p : points) t.labels.push_back(truth_files.card.LabelAt(p.head<2>()));
  if (!truth_files.card.normal.empty())
    t.normals =
        FootprintNormals(truth_files.card, points, reference.width, reference.height, &t.relief);
  else if (process.reconstruction.normals_searched)
    // A flat sample searched for normals: every estimated tilt is false tilt, which the report
    // must show as it does on a relief's flat areas.
    t.normals.assign(points.size(), Eigen::Vector3f::UnitZ());
  return t;
}

// The map against the card's true materials, and the homogeneous result for the same materials
// at the same directions.
void ScoreMapAgainstTruth(const Plan& plan, const std::string& dir, const SvbrdfMap& map,
                          const BasisView& basis, const TruthAtPixels& truth_at,
                          const sim::GroundTruthFiles& truth_files, SessionReport* report) {
  const std::vector<MerlBrdf>& truth = truth_at.materials;
  const std::vector<int>& labels = truth_at.labels;
  report->score = ScoreMap(map, basis, labels, truth);
  FloatPlanes error;  // per pixel, for a look at where the map is wrong
  error.width = report->process.reference_width;
  error.height = report->process.reference_height;
  error.planes["log_rmse"] = report->score.log_rmse;
  error.planes["label"].assign(labels.begin(), labels.end());
  error.attributes["meaning"] =
      "log_rmse: log-space RMSE against the true material, -1 off the card; label: the true "
      "material's index in materials.tsv, -1 off the card";
  if (!truth_at.normals.empty()) {
    report->normals = ScoreNormals(map, truth_at.normals, labels);
    error.planes["normal_error_deg"] = report->normals->error_deg;
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<float>& plane = error.planes[std::string("true_normal.") + "xyz"[axis]];
      for (const Eigen::Vector3f& n : truth_at.normals) plane.push_back(n[axis]);
    }
    error.attributes["meaning"] +=
        "; normal_error_deg: the estimated normal's angle to the true one (degrees); "
        "true_normal: the mean of the relief's normals over the pixel (sample frame; +z on a "
        "flat sample)";
  }
  WriteFloatPlanesExr(dir + "/ground_truth/error.exr", error);
  std::vector<double> homogeneous;
  const std::vector<std::size_t> bins = BinsOf(plan.directions);
  report->homogeneous_log_rmse.clear();
  for (const MerlBrdf& m : truth) {
    double sum = 0;
    for (const ChannelError& e : EvaluateHomogeneous(
             basis, m, bins,
             RidgeOptions{plan.reconstruction.components, plan.reconstruction.eta})) {
      homogeneous.push_back(e.log_rmse);
      sum += e.log_rmse / 3;
    }
    report->homogeneous_log_rmse.push_back(sum);
  }
  report->materials = truth_files.material_names;
  report->homogeneous_median_log_rmse = Median(homogeneous);
  report->scored = true;
}

// Each validation view's capture (renders/validation_NNN.exr, as the processing kept it)
// against the true materials rendered at every pixel's own directions, and the map's render
// against that truth: how much of the validation figure is the capture's own noise, which no
// model can remove, and how far the map is from the truth without it.
void ScoreValidationAgainstTruth(const Plan& plan, const std::string& dir, const SvbrdfMap& map,
                                 const BasisView& basis, const TruthAtPixels& truth_at,
                                 SessionReport* report) {
  // The truth between its tabulated samples, as the simulated camera renders it (from the
  // network, sim/synthetic_svbrdf.cpp): a nearest-bin truth steps by up to half a bin's change,
  // 5% near view 8's highlight, which the capture does not (docs/colour.md).
  // On a relief, each pixel's material on its true facets as the camera saw them: the values on
  // its footprint's facets averaged (a glossy ink's highlights are not those of the mean normal).
  // A flat truth scored a map's right normals as error (the files' sample's view 8: its brass
  // lettering's highlights, 0.59 of relative RMS from the capture).
  const PixelBrdf truth = [&truth_at, w = map.info.width](int x, int y, const Eigen::Vector3d& in,
                                                          const Eigen::Vector3d& out) {
    const std::size_t i = std::size_t(y) * w + x;
    const int label = truth_at.labels[i];
    if (label < 0) return std::array<double, 3>{};
    const MerlBrdf& material = truth_at.materials[std::size_t(label)];
    const auto brdf = [&material](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
      return material.LookupInterpolated(a, b);
    };
    const FootprintFacets& relief = truth_at.relief;
    if (relief.first.empty()) return brdf(in, out);
    if (relief.first[i] < 0) return SeenAsFlat(truth_at.normals[i], in, out, brdf);
    std::array<double, 3> sum{};
    for (int k = 0; k < kSub * kSub; ++k) {
      const std::array<double, 3> v =
          SeenAsFlat(relief.normals[std::size_t(relief.first[i] + k)], in, out, brdf);
      for (int c = 0; c < 3; ++c) sum[c] += v[c] / (kSub * kSub);
    }
    return sum;
  };
  report->validation_truth.clear();
  for (const ValidationSummary& v : report->process.validation) {
    const std::filesystem::path render(v.render);
    const std::string kept =
        dir + "/" + render.parent_path().string() + "/" + render.stem().string() + ".exr";
    if (!std::filesystem::is_regular_file(kept)) continue;  // a session from before they were kept
    const ValidationData captured = ReadValidationData(kept);
    const RgbImage truth_render = PredictAtPixels(captured, truth);
    const ValidationResult floor = Compare(captured, truth_render);
    // The truth's render in the capture's place, at the pixels' own points: the map against it
    // leaves the capture out, its sampling too (acq/capture_sampling.h).
    ValidationData true_view = captured;
    true_view.positions = {};
    true_view.captured = truth_render.rgb;
    const ValidationResult map_error =
        Compare(true_view, MapPixelBrdf(map, basis, plan.reconstruction.lookup));
    report->validation_truth.push_back({v.name, floor.median_delta_e2000, floor.relative_rms,
                                        map_error.median_delta_e2000, map_error.relative_rms});
  }
}

// The calibrated geometry against the simulated instrument's: points on a grid over the sample
// projected through the calibrated camera and pose, and through the true ones at the arms the
// gantry measured, at every board pose; and the camera centre the board alone would give.
void ScoreCalibration(const Plan& plan, const calib::CameraModel& true_camera,
                      SessionReport* report) {
  const SessionCalibration& c = report->process.calibration;
  std::vector<double> misalignment, eye_error_deg;
  for (const BoardPoseResult& b : c.boards) {
    if (!b.found || !b.arms_known) continue;
    const calib::Pose truth =
        sim::ViewFromArms(b.arms, plan.gantry.camera_distance_mm, plan.gantry.light_distance_mm, 1)
            .cam_from_sample;
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j) {
        const Eigen::Vector3d p((i / 4.0 - 0.5) * plan.sample.width_mm,
                                (j / 4.0 - 0.5) * plan.sample.height_mm, 0);
        const Eigen::Vector2d a = c.camera.Project(b.cam_from_sample * p);
        const Eigen::Vector2d t = true_camera.Project(truth * p);
        misalignment.push_back((a - t).norm());
      }
    // The camera's centre the board alone gives, as seen from the sample centre.
    const Eigen::Vector3d eye = b.cam_from_sample.Inverse().t, true_eye = truth.Inverse().t;
    eye_error_deg.push_back(
        RadToDeg(std::acos(std::min(1.0, eye.normalized().dot(true_eye.normalized())))));
  }
  if (misalignment.empty()) return;
  report->alignment_median_px = Median(misalignment);
  report->alignment_max_px = *std::max_element(misalignment.begin(), misalignment.end());
  report->board_eye_error_median_deg = Median(eye_error_deg);
  report->board_eye_error_max_deg = *std::max_element(eye_error_deg.begin(), eye_error_deg.end());
}

}  // namespace

bool HasGroundTruth(const std::string& session_dir) {
  return std::filesystem::is_regular_file(session_dir + "/ground_truth/ground_truth_labels.exr");
}

void ScoreAgainstGroundTruth(const Plan& plan, const std::string& session_dir,
                             SessionReport* report) {
  const sim::GroundTruthFiles truth = sim::ReadGroundTruth(session_dir + "/ground_truth");
  const SvbrdfMap map = ReadSvbrdfMap(session_dir + "/svbrdf.exr");
  const TruthAtPixels truth_at = TruthOfMap(plan, truth, report->process);
  const MappedBasis mapped = MappedBasis::Open(plan.reconstruction.basis_file);
  ScoreMapAgainstTruth(plan, session_dir, map, mapped.View(), truth_at, truth, report);
  ScoreValidationAgainstTruth(plan, session_dir, map, mapped.View(), truth_at, report);
  ScoreCalibration(plan, truth.camera, report);
}

}  // namespace acq
