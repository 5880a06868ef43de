// The plan (issue 8; docs/session-and-plan.md): one YAML file that says everything a session
// does. Loaded and validated completely before anything moves: unknown keys, wrong types, values
// out of range, missing files, directions the gantry cannot take; every error names
// file:line:column and says what to do.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acq/move_planner.h"
#include "brdf/basis_rows.h"
#include "brdf/directions.h"
#include "brdf/normal_search.h"
#include "brdf/pooled_model.h"
#include "core/colour_chart.h"
#include "core/sample_kind.h"
#include "hw/camera.h"
#include "hw/usb_transport.h"

namespace acq {

enum class Backend { kSim, kUsbAravis, kReplay };
const char* BackendName(Backend b);

// Each section of the plan is a struct with its reader (plan.cpp) and a Check() of its values
// rules; Check() throws UserError whose where() is the offending key (as spelled in the plan),
// which the reader turns into file:line:column.

struct SampleSpec {  // sample:
  double width_mm = 70, height_mm = 70;
  void Check() const;
};

struct GantrySpec {  // gantry:
  UsbDeviceId usb;
  GantryMotion motion;
  double camera_distance_mm = 1000, light_distance_mm = 1000;
  void Check() const;
};

struct CameraSpec {         // camera:
  std::string id;           // Aravis device id (usb+aravis); the simulated camera's otherwise
  CameraSettings settings;  // pixel format, gain; exposure: the bracket's first
  std::vector<double> bracket_us;  // empty: automatic bracket
  bool auto_bracket = false;
  // camera.colour_matrix (a Bayer camera): linear Rec. 709 = this x camera RGB, nine numbers row
  // by row, for a camera characterised before (docs/colour.md); the light's colour is left to
  // the Spectralon captures. Unset for a mono camera.
  std::optional<Eigen::Matrix3d> rec709_from_camera;
  // camera.colour_chart (a Bayer camera): true, a ColorChecker captured at the sample's first
  // pose, from which the processing fits rec709_from_camera (acq/colour_chart_fit.h);
  // not_fitted, the chart captured and colour_matrix used instead (a session whose chart could
  // not be fitted, processed again with a characterised camera's matrix: docs/colour.md).
  enum class Chart { kNone, kFitted, kNotFitted };
  Chart colour_chart = Chart::kNone;
  bool ChartCaptured() const { return colour_chart != Chart::kNone; }
  void Check() const;
  void CheckColour() const;  // a matrix for a colour camera only, and an invertible one
};

// Calibration (docs/calibration.md): the intrinsics from this many board captures, or from a
// lens calibrated before (intrinsics_file; then no intrinsics captures), with this mrcal lens
// model (its name is checked against mrcal by acqd, where `lensmodel_where` points).
struct CalibrationSpec {  // calibration:
  int intrinsics_captures = 30;
  std::string intrinsics_file;
  std::string lensmodel = "LENSMODEL_OPENCV4";
  std::string lensmodel_where;
  int board_width_n = 10, board_height_n = 10;
  double board_spacing_mm = 20;
  void Check() const;
};

// backend sim: the simulated world. The sample is a printed card of these measured materials
// (neural-BRDF fits), the light's intensity in the renderer's units, simulated time per wall
// second; the camera a pinhole of this size framing the card, or the lens of an mrcal
// .cameramodel (its size too).
struct SimSpec {  // sim:
  std::vector<std::string> materials;
  SampleKind sample = SampleKind::kCard;  // sim.sample: the layout of the materials, built in
  std::optional<SampleFile> sample_file;  // or sim.sample: {labels|weights: FILE}
  std::uint64_t seed = 1;
  double light_intensity = 2e5;
  double time_scale = 10;
  // The simulated world waits for the operator's `acqctl confirm` at every placement, as the
  // instrument does, instead of placing items itself (the prompt path in simulation).
  bool operator_prompts = false;  // sim.operator
  int image_width = 320, image_height = 320;
  // sim.pixel_samples: N, the camera's pixels integrated over N x N points
  // (sim::InstrumentOptions::pixel_samples); 1: each pixel's centre.
  int pixel_samples = 1;
  std::string camera_model;
  // sim.camera_filter: the simulated sensor's Bayer filter ("RGGB", ..., "none"); unset: the
  // filter camera.pixel_format names. sim.light_rgb: the light's colour; unset: warm for a
  // colour camera, white for a mono one (sim/instrument.h).
  std::optional<Cfa> camera_filter;
  std::optional<Eigen::Vector3d> light_rgb;
  // sim.relief: {slope_deg: S, fibre_deg: F}: the card embossed where it is printed and raised at
  // its border, edges of steepest slope S degrees, with paper-fibre noise of RMS slope F
  // (sim/relief.h, issue 19); or {height_map: FILE}: heights from a file of the sample layout's
  // size (sim::ReadHeightMap); unset: flat.
  struct Relief {
    double slope_deg = 10, fibre_deg = 0;
    std::string height_map;  // resolved; empty: the built-in relief
  };
  std::optional<Relief> relief;
  // sim.chart: how the operator lays the colour chart (issue 16's bad input): {covered_mm: [x0,
  // y0, x1, y1]}, a grey card lying over that rectangle of the sample plane (sim::ChartScene);
  // {laid: false}, the chart forgotten (the sample captured in its place); {turned_deg: 90}, the
  // chart laid turned counter-clockwise by 90, 180 or 270 degrees (core/colour_chart.h).
  struct Chart {
    std::optional<std::array<double, 4>> covered_mm;
    bool laid = true;
    ChartTurn turned = ChartTurn::kNone;
  };
  Chart chart;
  void Check() const;
};

struct ReconstructionSpec {  // reconstruction:
  std::string basis_file;
  std::string basis_where, components_where;  // file:line:column of the keys, for later checks
  int components = kDefaultComponents;        // k
  double eta = kDefaultEta;
  RowLookup lookup = RowLookup::kNearest;
  int row_tile = 1;  // PixelSolveOptions::row_tile
  ReconstructionMethod method = kDefaultReconstructionMethod;
  int groups = 0;  // PooledOptions::groups (0: chosen by held-out views)
  double design_sigma_deg = kDefaultDesignSigmaDeg;  // PooledOptions::design_sigma_deg
  bool normals = false;  // reconstruction.normals: each pixel's normal estimated (normal_search.h)
  double normals_prior = kDefaultNormalsPrior;              // NormalSearchOptions::prior
  bool normals_mixed_pixels = kDefaultNormalsMixedPixels;   // NormalSearchOptions::mixed_pixels
  int normals_trimmed_views = kDefaultNormalsTrimmedViews;  // NormalSearchOptions::trimmed_views
  // NormalSearchOptions::max_uncertainty_deg
  double normals_max_uncertainty_deg = kDefaultNormalsMaxUncertaintyDeg;
  double normals_evidence = kDefaultNormalsEvidence;          // NormalSearchOptions::evidence
  double normals_score_min_cos = kDefaultNormalsScoreMinCos;  // NormalSearchOptions::score_min_cos
  bool normals_view_weights = kDefaultNormalsViewWeights;     // NormalSearchOptions::view_weights
  double normals_min_tilt_deg = kDefaultNormalsMinTiltDeg;    // NormalSearchOptions::min_tilt_deg
  bool normals_same_centre = kDefaultNormalsSameCentre;       // NormalSearchOptions::same_centre
  // NormalSearchOptions::mixed_same_group
  bool normals_mixed_same_group = kDefaultNormalsMixedSameGroup;
  // NormalSearchOptions::confirmation (reconstruction.normals_confirm)
  NormalConfirmation normals_confirmation = kDefaultNormalsConfirmation;
  // reconstruction.pixel_footprint: the map records what the camera's pixels integrated over
  // (SvbrdfMapInfo::pixel_spread_px, CameraPixelSpreadPx), and its renders average each pixel
  // over it where its normals vary; false: every render at the pixel's centre.
  bool pixel_footprint = true;
  void Check() const;
};

struct Plan {
  std::string path;  // the plan file; relative paths in it are relative to its folder
  Backend backend = Backend::kSim;
  std::string output;          // the session directory
  std::string replay_session;  // kReplay: the recorded session served again
  SampleSpec sample;
  GantrySpec gantry;
  CameraSpec camera;

  // directions: the sample's, from a file or, optimised, what chose them.
  std::string directions_file;
  std::vector<Direction> directions;
  // directions.optimize: chosen at load for the basis (0: read from directions_file).
  int optimize_n = 20, optimize_candidates = 1000;
  std::uint64_t optimize_seed = 1;
  // Validation views: captured like the sample's, never used to reconstruct; the map's
  // renders are compared with them (optional).
  std::string validation_file;
  std::vector<Direction> validation;

  CalibrationSpec calibration;
  bool spectralon = true;
  SimSpec sim;
  ReconstructionSpec reconstruction;
};

// Reads and validates; throws UserError ("plan.yaml:12:5: ...") at the first problem. Checks
// that the directions can be taken (reach and collision rules) but opens no device. Relative
// paths in the plan are relative to `relative_to`, by default the plan file's folder (a plan
// copied into a session is read relative to where it was written, issue 21).
Plan LoadPlan(const std::string& path, const std::string& relative_to = {});

}  // namespace acq
