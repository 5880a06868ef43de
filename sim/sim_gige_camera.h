// The simulated camera (issue 6): a real GigE Vision device on a loopback address, Aravis's fake
// camera (ArvGvFakeCamera), whose frames our renderer fills. It serves the standard features
// (ExposureTime, Gain, PixelFormat with Mono8/Mono12/Mono16, Width, Height, software trigger) so
// Aravis's own tools and our driver see an ordinary camera. Each frame renders the sample from
// where the simulated gantry holds the camera and the light at that moment (the `view` callback),
// then exposes it through the sensor model at the frame's exposure and gain.
//
// Loopback facts (measured here): two fake cameras on one address answer as one, so each gets
// its own 127.0.0.N, added to lo (the tests run in a private network namespace, see
// tests/run_in_netns.sh); Aravis must not use its packet socket on loopback.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "calib/camera_model.h"
#include "core/cfa.h"
#include "core/gantry_geometry.h"
#include "sim/sample_renderer.h"

namespace acq::sim {

struct SimView {
  calib::Pose cam_from_sample;
  PointLight light;
};

// Where the gantry's arms put the camera (looking at the sample centre, image x horizontal) and
// the light, at the arms' distances: what the simulated camera renders from while the simulated
// gantry holds those angles (EmulatedUsbGantry::WithFirmware(... Measured())).
SimView ViewFromArms(const ArmAngles& arms, double camera_distance_mm, double light_distance_mm,
                     double light_intensity);

struct SimCameraOptions {
  std::string address = "127.0.0.2";
  std::string serial = "ACQSIM01";
  SensorModel sensor;
  int channel = -1;  // the colour channel a mono sensor sees (0, 1, 2), or -1: luminance
  // A colour camera (issue 16): the Bayer filter over its photosites (kNone: mono), which it
  // offers as Bayer..8/12/16 of that phase, and its channels' sensitivities, which are not
  // Rec. 709's: camera RGB = camera_from_rec709 x linear Rec. 709 radiance, before the mosaic.
  Cfa cfa = Cfa::kNone;
  Eigen::Matrix3d camera_from_rec709 = Eigen::Matrix3d::Identity();
  int ray_grid_step_px = 4;
  std::uint64_t seed = 1;
};

// One frame as the simulated camera produced it, for tests to compare against what arrived.
struct ServedFrame {
  std::uint64_t index = 0;  // 1, 2, ... since start
  int width = 0, height = 0, max_dn = 0;
  double exposure_us = 0, gain_db = 0;
  std::vector<std::uint16_t> counts;
};

class SimGigECamera {
 public:
  SimGigECamera(RenderScene scene, calib::CameraModel model, std::function<SimView()> view,
                SimCameraOptions options = {});
  ~SimGigECamera();
  SimGigECamera(const SimGigECamera&) = delete;
  SimGigECamera& operator=(const SimGigECamera&) = delete;

  const std::string& address() const { return options_.address; }
  const std::string& serial() const { return options_.serial; }
  // The camera stops answering (powered off, cable pulled): its control and stream ports close.
  void Disappear();
  // Back with its power-on settings (the driver must apply its own again).
  void Reappear();
  // What lies under the gantry from the next frame on (the card, the board, the Spectralon).
  void SetScene(RenderScene scene);
  // Fraction of stream packets the camera drops (Aravis's gvsp-lost-ratio).
  void SetLostPacketRatio(double ratio);

  ServedFrame LastServed() const;
  double last_render_seconds() const;
  std::uint64_t frames_served() const;

  // Called from the fake camera's thread (public for the C callback only).
  void Fill(void* buffer, std::uint32_t exposure_us, std::uint32_t gain_raw, std::uint32_t format);

 private:
  void Start();
  void Stop();

  RenderScene scene_;
  calib::CameraModel model_;
  std::function<SimView()> view_;
  SimCameraOptions options_;
  std::string genicam_path_;   // our GenICam description, written once beside the temp files
  void* gv_camera_ = nullptr;  // ArvGvFakeCamera*
  double lost_ratio_ = 0;
  mutable std::mutex mutex_;
  bool have_render_ = false;
  SimView rendered_view_;
  std::vector<float> radiance_;  // of rendered_view_, the channel the sensor sees
  ServedFrame last_;
  double render_seconds_ = 0;
};

// The fake camera's GenICam description with the standard names our driver and users expect:
// ExposureTime (us), Gain (dB, stored in centi-dB in the gain register), and as PixelFormat
// Mono8, Mono12, Mono16 for a mono sensor or the three Bayer depths of its filter's phase.
std::string SimCameraGenicamXml(Cfa cfa = Cfa::kNone);

// A plausible colour camera's channel sensitivities against linear Rec. 709 (rows R, G, B of the
// camera; each row sums to 1, so grey stays grey): broad overlapping dye filters, green's
// leaking most. Documented in docs/colour.md; the pipeline must calibrate it (a colour chart, or
// the plan's camera.colour_matrix).
Eigen::Matrix3d PlausibleCameraCrosstalk();

// What a colour sensor's photosites see: camera RGB (camera_from_rec709 x the linear Rec. 709
// radiance), each photosite keeping the channel its filter passes.
std::vector<float> MosaicOf(const RadianceImage& rec709, const Eigen::Matrix3d& camera_from_rec709,
                            Cfa cfa);

}  // namespace acq::sim
