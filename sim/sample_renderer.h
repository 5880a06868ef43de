// What the simulated camera sees (issue 6): a flat sample in the sample plane (z = 0, sample
// frame of docs/calibration.md) under a point light, through any mrcal lens model, and the
// sensor that turns that radiance into counts.
//
// Radiometry, in arbitrary but consistent units: a point light of intensity I at distance d
// gives irradiance E = I cos(theta_i) / d^2 on the sample; the radiance towards the camera is
// L = f_r(wi, wo) E (so a Lambertian patch of albedo rho gives L = rho I cos(theta_i) / (pi d^2)).
// The sensor collects electrons = L * exposure * quantum_scale, adds shot noise (Poisson) and
// read noise (Gaussian), clips at the full well, scales by the gain and quantises to the pixel
// format's range, saturating at its maximum.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calib/board.h"
#include "calib/camera_model.h"
#include "core/colour_chart.h"
#include "sim/synthetic_svbrdf.h"

namespace acq::sim {

struct RenderScene {
  enum class Kind { kCard, kChessboard, kSpectralon, kChart } kind = Kind::kCard;
  double sample_size_mm = 100;  // the square Spectralon board centred at the origin (the card:
                                // its own SyntheticSvbrdf::sample_size_mm)
  SyntheticSvbrdf card;         // kCard: material labels over the sample
  std::vector<GroundTruth> materials;
  std::vector<std::string> material_names;  // for the ground truth written beside a session
  // kChessboard: its corner grid centred at the origin of its own frame, x and y along the
  // frame's, z its normal towards the camera (the sample frame a board lying flat defines),
  // printed inside a white margin one square wide.
  calib::BoardSpec board{10, 10, 10};
  // Where the chessboard's frame is: identity lies it flat on the sample plane (the extrinsics
  // captures); a tilted pose is a board held up for the intrinsics captures. The dark cloth
  // (background) is then the board's own backing plane.
  calib::Pose sample_from_chessboard;
  double board_black = 0.04, board_white = 0.85;  // Lambertian albedos of its squares
  double spectralon_albedo = 0.99;                // kSpectralon: Lambertian
  // kChart: a ColorChecker Classic flat on the sample plane (core/colour_chart.h), its patches
  // Lambertian with their reference colours on a black body.
  ChartLayout chart;
  double chart_body_albedo = 0.03;
  // A grey card lying over part of the chart (the operator's occlusion), on the sample plane.
  std::optional<Eigen::AlignedBox2d> chart_cover;
  double chart_cover_albedo = 0.18;
  double background_albedo = 0.02;  // the dark cloth around the sample (Lambertian)
  // The points per axis at which a camera pixel samples the scene, spread evenly over the pixel
  // (InstrumentOptions::pixel_samples); 1: the pixel's centre alone.
  int pixel_samples = 1;
};

struct PointLight {
  Eigen::Vector3d position_mm{0, 0, 1000};  // in the sample frame
  double intensity = 1e6;                   // radiance units x mm^2
  // Its colour: each linear Rec. 709 channel's share of `intensity` (white: 1, 1, 1). The
  // colour instrument's light is warm (InstrumentOptions::light_rgb); a Spectralon capture
  // calibrates it out per channel.
  Eigen::Vector3d rgb{1, 1, 1};
};

// Linear radiance per pixel of the camera's imager, RGB interleaved (3 floats per pixel).
struct RadianceImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  // One channel (0, 1, 2) or, for -1, luminance (Rec. 709 weights): what a mono sensor sees.
  std::vector<float> Channel(int channel) const;
};

// Every pixel's radiance, the mean over scene.pixel_samples^2 points spread evenly over it;
// every point's ray (mrcal unprojection, on a grid of `ray_grid_step_px` and interpolated
// between) meets the sample plane; rays that miss the plane see black.
RadianceImage RenderRadiance(const RenderScene& scene, const calib::CameraModel& camera,
                             const calib::Pose& cam_from_sample, const PointLight& light,
                             int ray_grid_step_px = 4);

// The radiance of the scene at one sample point seen from `eye` (both in the sample frame).
std::array<double, 3> RadianceAt(const RenderScene& scene, const Eigen::Vector2d& point,
                                 const Eigen::Vector3d& eye, const PointLight& light);

struct SensorModel {
  double quantum_scale = 1.0;  // electrons per radiance unit per microsecond of exposure
  double full_well_e = 20000;
  double read_noise_e = 4;
  double black_level_dn = 0;  // added before quantisation (in counts at the format's depth)
  bool noise = true;
  // Counts per electron at `max_dn` full scale and gain_db.
  double CountsPerElectron(int max_dn, double gain_db) const;
  // Mean counts per microsecond per radiance unit: what an HDR merge (counts/us at 0 dB) gives
  // for radiance 1, i.e. what a Spectralon capture calibrates on the instrument.
  double CountsPerRadianceUs(int max_dn) const {
    return quantum_scale * CountsPerElectron(max_dn, 0);
  }
};

// Counts at `max_dn` (255, 4095, 65535) full scale for one exposure; deterministic for a seed.
std::vector<std::uint16_t> Expose(const std::vector<float>& radiance, double exposure_us,
                                  double gain_db, int max_dn, const SensorModel& sensor,
                                  std::uint64_t seed);

}  // namespace acq::sim
