#include "sim/instrument.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "calib/extrinsics.h"
#include "calib/synthetic_board.h"
#include "core/error.h"
#include "sim/ground_truth.h"
#include "sim/sample_layouts.h"

namespace acq::sim {
namespace {

// The pinhole whose image holds the card with a margin (it fills 80% of the shorter side) at
// the arm's distance: small frames keep a simulated session quick.
calib::CameraModel FramingPinhole(const InstrumentOptions& o) {
  const int w = o.image_width, h = o.image_height;
  const double f = 0.8 * std::min(w, h) * o.camera_distance_mm / o.sample_size_mm;
  return calib::CameraModel("LENSMODEL_PINHOLE", {f, f, (w - 1) / 2.0, (h - 1) / 2.0}, w, h);
}

std::string Millimetres(double mm) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", mm);
  return text;
}

std::vector<std::string> MaterialNames(const std::vector<std::string>& material_files) {
  std::vector<std::string> names;
  for (const std::string& f : material_files)
    names.push_back(std::filesystem::path(f).stem().string());
  return names;
}

// The instrument's sample: a file's layout, or a built-in one at 0.1 mm per label cell, a few
// times finer than a camera pixel. One function, because the scoring must rebuild exactly the
// mixtures the camera saw.
MixedSample InstrumentSample(const InstrumentOptions& o) {
  if (o.sample_file)
    return ReadSampleFile(*o.sample_file, MaterialNames(o.material_files), o.sample_size_mm);
  const int cells = std::max(16, int(o.sample_size_mm * 10));
  return MakeSample(o.sample, cells, cells, o.sample_size_mm, int(o.material_files.size()), o.seed);
}

// The heights of the relief the options ask for on `layout`; empty when flat.
std::vector<float> InstrumentRelief(const InstrumentOptions& o, const SyntheticSvbrdf& layout) {
  if (!o.height_map_file.empty())
    return ReadHeightMap(o.height_map_file, layout.width, layout.height, kPngHeightFullScalePx);
  if (o.relief) return CardRelief(layout, *o.relief);
  return {};
}

}  // namespace

void InstrumentOptions::Check() const {
  if (material_files.empty())
    throw UserError(where, "the simulated card has no materials",
                    "list neural-BRDF fits (.h5) for its inks in sim.materials");
  if (material_files.size() > 255)
    throw UserError(where, "the simulated card holds at most 255 materials");
  if (!(sample_size_mm > 0) || !(camera_distance_mm > 0) || !(light_distance_mm > 0) ||
      !(light_intensity > 0))
    throw UserError(where,
                    "the sample's size, the arms' distances and the light's intensity "
                    "must be positive");
  if (camera_model_file.empty() &&
      (image_width < 16 || image_height < 16 || image_width > 16384 || image_height > 16384))
    throw UserError(where, "the simulated camera's image must be 16 to 16384 pixels a side");
  if (held_board_poses < 0) throw UserError(where, "a negative number of held board poses");
  if (pixel_samples < 1 || pixel_samples > kMaxPixelSamples)
    throw UserError(where, "the camera's pixel samples per axis must be 1 to " +
                               std::to_string(kMaxPixelSamples));
  if (relief && !height_map_file.empty())
    throw UserError(where, "both a built-in relief and a height map", "give one of them");
  if (relief) relief->Check();
  // The sample's files read now (cheap: a layout, not the materials), their errors named.
  if (!sample_file && height_map_file.empty()) return;
  const SyntheticSvbrdf layout = InstrumentSample(*this).layout;
  InstrumentRelief(*this, layout);
  // A file spans the sample's width with square pixels: another shape than the plan's sample
  // leaves part of the sample without material, or puts material off it.
  const double file_height_mm = sample_size_mm * layout.height / layout.width;
  if (sample_file && sample_height_mm > 0 &&
      std::abs(file_height_mm - sample_height_mm) > 0.01 * sample_height_mm)
    throw UserError(sample_file->path,
                    "is " + std::to_string(layout.width) + "x" + std::to_string(layout.height) +
                        " pixels: across the sample's " + Millimetres(sample_size_mm) +
                        " mm it is " + Millimetres(file_height_mm) + " mm high, the sample " +
                        Millimetres(sample_height_mm) + " mm",
                    "give a file of the sample's shape (sample.size_mm), its pixels square");
}

Instrument::Instrument(const InstrumentOptions& options) : options_(options) {
  options_.Check();
  for (const std::string& path : options_.material_files)
    networks_.push_back(NeuralBrdf::Load(path));
  scene_.kind = RenderScene::Kind::kCard;
  scene_.sample_size_mm = options_.sample_size_mm;
  scene_.pixel_samples = options_.pixel_samples;
  const MixedSample sample = InstrumentSample(options_);
  scene_.card = sample.layout;
  const std::vector<float> heights = InstrumentRelief(options_, scene_.card);
  if (!heights.empty()) SetNormalsFromHeight(&scene_.card, heights);
  for (NeuralBrdf& network : networks_) base_truths_.push_back({&network, nullptr});
  scene_.materials = sample.Truths(base_truths_);
  scene_.material_names = sample.Names(MaterialNames(options_.material_files));
  model_ = options_.camera_model_file.empty()
               ? FramingPinhole(options_)
               : calib::CameraModel::Read(options_.camera_model_file);
  scene_.board = options_.board;
  PlaceHeldBoards();
  gantry_ = std::make_unique<EmulatedUsbGantry>(options_.firmware, options_.usb);
  SimCameraOptions camera;
  camera.seed = options_.seed;
  camera.cfa = options_.camera_filter;
  if (camera.cfa != Cfa::kNone) camera.camera_from_rec709 = PlausibleCameraCrosstalk();
  sensor_ = camera.sensor;
  const double camera_mm = options_.camera_distance_mm, light_mm = options_.light_distance_mm;
  const double intensity = options_.light_intensity;
  const Eigen::Vector3d light_rgb =
      options_.light_rgb.value_or(camera.cfa != Cfa::kNone ? kWarmLight : Eigen::Vector3d(1, 1, 1));
  camera_ = std::make_unique<SimGigECamera>(
      scene_, model_,
      [this, camera_mm, light_mm, intensity, light_rgb] {
        const ArmAngles arms =
            gantry_->WithFirmware([](SimGantryFirmware& f) { return f.Measured(); });
        SimView view = ViewFromArms(arms, camera_mm, light_mm, intensity);
        view.light.rgb = light_rgb;
        return view;
      },
      camera);
}

// The operator's board poses for the intrinsics: spread over the view of the camera straight
// above the sample (where the sequencer holds it for these captures), tilted up to 35 degrees
// towards any side, within 5% of the arm's distance.
void Instrument::PlaceHeldBoards() {
  const int n = options_.held_board_poses;
  if (n == 0) return;
  const double distance = options_.camera_distance_mm;
  calib::BoardPoseSampling sampling;
  sampling.min_distance_mm = 0.95 * distance;
  sampling.max_distance_mm = 1.05 * distance;
  sampling.max_tilt_deg = 35;
  sampling.seed = options_.seed;
  const std::vector<calib::Pose> cam_from_board =
      calib::SampleBoardPoses(model_, scene_.board, n, sampling);
  if (int(cam_from_board.size()) < n) {
    const double view_mm = model_.width() / model_.intrinsics()[0] * distance;
    char why[160];
    std::snprintf(why, sizeof why,
                  "the board (%d x %d corners, %.1f mm squares) does not fit the simulated "
                  "camera's view, %.0f mm across",
                  scene_.board.width_n, scene_.board.height_n, scene_.board.spacing_mm, view_mm);
    throw UserError(options_.where, why, "give calibration.board a smaller spacing_mm or size");
  }
  const calib::Pose sample_from_cam =
      calib::CamFromSampleLookingAtCentre({0, 0, distance}).Inverse();
  // mrcal's board frame to the chessboard's (the sample frame a flat board defines).
  const calib::Pose board_from_chessboard = calib::SampleFromBoard(scene_.board).Inverse();
  for (const calib::Pose& p : cam_from_board)
    held_boards_.push_back(sample_from_cam.Compose(p).Compose(board_from_chessboard));
}

double Instrument::LightIntensityInCounts(int max_dn) const {
  return options_.light_intensity * sensor_.CountsPerRadianceUs(max_dn);
}

void Instrument::Place(const Placement& p) {
  RenderScene scene = scene_;
  switch (p.item) {
    case Item::kSpectralon:
      scene.kind = RenderScene::Kind::kSpectralon;
      break;
    case Item::kBoard:
      scene.kind = RenderScene::Kind::kChessboard;  // flat on the sample plane unless held
      if (p.held_pose > 0) {
        if (p.held_pose > int(held_boards_.size()))
          throw UserError(options_.where, "no held board pose " + std::to_string(p.held_pose),
                          "the instrument places " + std::to_string(held_boards_.size()));
        scene.sample_from_chessboard = held_boards_[std::size_t(p.held_pose) - 1];
      }
      break;
    case Item::kChart:
      if (!options_.chart_laid) break;  // forgotten: the camera sees the sample
      scene.kind = RenderScene::Kind::kChart;
      scene.chart_cover = options_.chart_cover;
      scene.chart.turn = options_.chart_turn;
      break;
    case Item::kSample:
      break;
  }
  camera_->SetScene(std::move(scene));
}

std::vector<MerlBrdf> TruthTables(const InstrumentOptions& options, bool colour) {
  std::vector<MerlBrdf> tables;
  for (const std::string& path : options.material_files) {
    MerlBrdf table = NeuralBrdf::Load(path).Tabulate();
    tables.push_back(colour ? std::move(table) : LuminanceOf(table));
  }
  if (options.sample == SampleKind::kCard && !options.sample_file) return tables;
  return InstrumentSample(options).Tables(tables);
}

void Instrument::WriteGroundTruth(const std::string& dir) const {
  sim::WriteGroundTruth(dir, scene_, model_);
}

}  // namespace acq::sim
