// The simulated instrument behind `backend: sim` (issue 8): the gantry firmware presented as a
// USB device by umockdev, and the GigE Vision camera on 127.0.0.2 rendering the card from where
// that gantry holds the arms. acqd reaches both through its real drivers (UsbTransport,
// AravisCamera), exactly as it reaches the instrument.
//
// Both need their environment: umockdev's preload library, and a loopback that carries
// 127.0.0.2 (a private network namespace). acqd re-executes itself inside both when the plan asks
// for the sim backend (ReexecForSim).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "acq/plan.h"
#include "brdf/neural_brdf.h"
#include "session/capture.h"
#include "sim/sim_gige_camera.h"
#include "sim/usb_gantry_device.h"

namespace acq {

// True when this process can host the simulated world.
bool SimEnvironmentReady();
// Replaces this process with itself inside a private network namespace with 127.0.0.2 on its
// loopback and umockdev's preload library; returns only when that cannot be done (with why).
std::string ReexecForSim(int argc, char** argv);

class SimWorld {
 public:
  explicit SimWorld(const Plan& plan);
  const std::string& camera_address() const { return camera_->address(); }
  const UsbDeviceId& usb_id() const { return usb_; }
  sim::EmulatedUsbGantry& gantry() { return *gantry_; }
  const calib::CameraModel& camera_model() const { return model_; }
  // The light's intensity in the HDR images' units (counts per us at 0 dB, x mm^2): what a
  // Spectralon capture measures on the instrument; here the simulated sensor's own scale.
  double LightIntensityInCounts(PixelFormat format) const;
  // Puts `item` under the gantry in place of the operator: "sample" (the card), "spectralon",
  // "board" (the chessboard flat on the sample plane, defining the sample frame) or "board/K"
  // (the K-th held board pose of the intrinsics captures, 1-based).
  void Place(const std::string& item);
  // The true material under each sample-plane point (mm), an index into TruthTables(); -1 off
  // the card.
  std::vector<int> LabelsAt(const std::vector<Eigen::Vector3d>& points) const;
  // The card's materials tabulated on the MERL grid as the simulated mono camera records them
  // (luminance in every channel).
  std::vector<MerlBrdf> TruthTables() const;
  // Writes the card's ground truth (labels, material names, camera model) into `dir`.
  void WriteGroundTruth(const std::string& dir) const;

 private:
  void PlaceHeldBoards(const Plan& plan);

  UsbDeviceId usb_;
  std::vector<calib::Pose> held_boards_;  // sample_from_chessboard per intrinsics capture
  std::vector<NeuralBrdf> networks_;
  sim::RenderScene scene_;
  calib::CameraModel model_;
  sim::SensorModel sensor_;
  double light_intensity_ = 0;
  std::unique_ptr<sim::EmulatedUsbGantry> gantry_;
  std::unique_ptr<sim::SimGigECamera> camera_;
};

}  // namespace acq
