// The simulated instrument behind `backend: sim` (issues 8, 21): the gantry firmware presented
// as a USB device by umockdev, and the GigE Vision camera on 127.0.0.2 rendering the card from
// where that gantry holds the arms. acqd reaches both through its real drivers (UsbTransport,
// AravisCamera), exactly as it reaches the instrument; it fills InstrumentOptions from the plan.
// Both devices need their environment (sim/environment.h).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "brdf/merl_brdf.h"
#include "brdf/neural_brdf.h"
#include "calib/board.h"
#include "calib/camera_model.h"
#include "core/colour_chart.h"
#include "core/sample_kind.h"
#include "core/session_vocabulary.h"
#include "sim/gantry_firmware.h"
#include "sim/relief.h"
#include "sim/sim_gige_camera.h"
#include "sim/usb_gantry_device.h"

namespace acq::sim {

struct InstrumentOptions {
  std::vector<std::string> material_files;  // neural-BRDF fits (.h5): the card's inks
  SampleKind sample = SampleKind::kCard;    // how the materials are laid out (sample_layouts.h)
  std::optional<SampleFile> sample_file;    // or a file lays them out (overrides `sample`)
  double sample_size_mm = 70;               // the card's side; a file's: its width, square pixels
  // The plan's sample height: a file's shape must agree with it (0: unchecked).
  double sample_height_mm = 0;
  double camera_distance_mm = 1000, light_distance_mm = 1000;
  double light_intensity = 2e5;  // the renderer's units x mm^2
  calib::BoardSpec board{10, 10, 20};
  int held_board_poses = 0;  // poses of the board held up for the intrinsics captures
  // The camera: this lens (an mrcal .cameramodel, whose size it has), or else a pinhole of
  // this size whose image holds the card with a margin at the arm's distance.
  std::string camera_model_file;
  int image_width = 320, image_height = 320;
  // A colour camera (issue 16): its Bayer filter (kNone: mono), with the cross-talk of
  // PlausibleCameraCrosstalk(); and the light's colour, unset: kWarmLight for a colour camera,
  // white for a mono one (whose record is luminance under white light, TruthTables).
  Cfa camera_filter = Cfa::kNone;
  std::optional<Eigen::Vector3d> light_rgb;
  // Relief on the sample (issue 19): the card embossed and its border raised (relief.h), each
  // point rendered in its facet's frame; unset: flat. Boards, chart and Spectralon stay flat.
  std::optional<ReliefOptions> relief;
  // The colour chart as the operator lays it (issue 16's bad input): partly under a grey card
  // (this rectangle of the sample plane, mm), or not at all (the sample left in its place).
  std::optional<Eigen::AlignedBox2d> chart_cover;
  bool chart_laid = true;
  ChartTurn chart_turn = ChartTurn::kNone;  // laid turned from its layout
  // The camera's pixels integrate the radiance over this many points per axis, spread evenly
  // over each (1: a pixel is its centre's point). A real sensor integrates over its pixel; at
  // one point a pixel straddling a relief's facets sees one of them, integrated their mean (what
  // that changes for the normals: docs/reconstruction.md, "The files sample's view 8"). Every
  // frame changes with it; the render's time grows as its square.
  int pixel_samples = 1;
  static constexpr int kMaxPixelSamples = 8;
  // Or the relief from a height map (ReadHeightMap; heights in the sample layout's cells: a file
  // sample's pixels, or the built-in samples' 0.1 mm cells), of the layout's size.
  std::string height_map_file;
  FirmwareOptions firmware;
  EmulatedUsbOptions usb;
  std::uint64_t seed = 1;
  std::string where = "the simulated instrument";  // what its errors name (the plan)
  // Throws UserError (naming `where`, or the file) for options no instrument can be built
  // from; reads the sample's files, so that their errors come before anything moves.
  void Check() const;
};

class Instrument {
 public:
  explicit Instrument(const InstrumentOptions& options);
  Instrument(const Instrument&) = delete;
  Instrument& operator=(const Instrument&) = delete;

  const std::string& camera_address() const { return camera_->address(); }
  const EmulatedUsbOptions& usb() const { return options_.usb; }
  // The light's intensity in the HDR images' units (counts per us at 0 dB, x mm^2) at a
  // format's full scale: what a Spectralon capture measures on the instrument.
  double LightIntensityInCounts(int max_dn) const;
  // Puts `p` under the gantry in place of the operator; UserError for a held board pose the
  // instrument has not placed (beyond held_board_poses).
  void Place(const Placement& p);
  // Writes the card's ground truth (sim/ground_truth.h) into `dir`.
  void WriteGroundTruth(const std::string& dir) const;

 private:
  void PlaceHeldBoards();

  InstrumentOptions options_;
  std::vector<calib::Pose> held_boards_;  // sample_from_chessboard per intrinsics capture
  std::vector<NeuralBrdf> networks_;
  std::vector<GroundTruth> base_truths_;  // one per network; the scene's mixtures point here
  RenderScene scene_;
  calib::CameraModel model_;
  SensorModel sensor_;
  std::unique_ptr<EmulatedUsbGantry> gantry_;
  std::unique_ptr<SimGigECamera> camera_;
};

// A halogen lamp's colour near 3000 K in linear Rec. 709, green 1 (its blue a little over a
// third of its red): what the colour instrument's light is unless the plan says otherwise.
inline const Eigen::Vector3d kWarmLight{1.38, 1.0, 0.55};

// What a map of the instrument's materials should hold: each tabulated, in linear Rec. 709 for a
// colour camera, in luminance (the same value thrice) for a mono one; for a sample other than the
// card, the tables of its mixtures in the order of its labels (the layout the instrument builds).
std::vector<MerlBrdf> TruthTables(const InstrumentOptions& options, bool colour);

}  // namespace acq::sim
