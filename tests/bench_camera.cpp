// Benchmark (issue 6): the simulated camera at full size through our Aravis driver over
// loopback GigE Vision: sustained frame rate, MB/s and incomplete frames at 2048 x 2048 Mono16,
// and the renderer's time per frame (a printed card of measured materials, 2048 x 2048).
//
//   tools/bench_camera.sh [frames=40]     (raises net.core.rmem_max when run as root, then
//                                           runs this inside tests/run_in_netns.sh)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "brdf/neural_brdf.h"
#include "calib/synthetic_board.h"
#include "hw/aravis_camera.h"
#include "sim/sim_gige_camera.h"

using namespace acq;
using Clock = std::chrono::steady_clock;

namespace {

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(5, std::atoi(argv[1])) : 40;
  const int size = 2048;  // the fake camera's sensor
  std::vector<NeuralBrdf> networks;
  for (const char* name : {"white-paint", "brass", "black-fabric", "pink-jasper"})
    networks.push_back(NeuralBrdf::Load(std::string(ACQ_DATA_DIR) + "/nbrdf/merl/" + name + ".h5"));
  sim::RenderScene scene;
  scene.kind = sim::RenderScene::Kind::kCard;
  scene.sample_size_mm = 100;
  scene.card = sim::MakeCardLayout(1024, 1024, scene.sample_size_mm, 4, 7);
  for (const NeuralBrdf& n : networks) scene.materials.push_back({&n, nullptr});
  // The card fills about 80% of the frame from 500 mm.
  const double f = 0.8 * size * 500 / scene.sample_size_mm;
  const calib::CameraModel model("LENSMODEL_PINHOLE", {f, f, (size - 1) / 2.0, (size - 1) / 2.0},
                                 size, size);
  sim::SimView view;
  view.cam_from_sample = calib::CamFromSampleLookingAtCentre({0, 0, 500});
  view.light.position_mm = {300, 200, 600};
  view.light.intensity = 2e5;

  // The renderer alone: each call a new light position, as each pose of a session is.
  const int renders = 3;
  auto start = Clock::now();
  for (int i = 0; i < renders; ++i) {
    sim::PointLight light = view.light;
    light.position_mm.x() += 10 * i;
    sim::RenderRadiance(scene, model, view.cam_from_sample, light);
  }
  const double render_s = Since(start) / renders;
  const std::vector<float> radiance(std::size_t(size) * size, 0.05f);
  start = Clock::now();
  for (int i = 0; i < renders; ++i) sim::Expose(radiance, 10000, 0, 65535, {}, std::uint64_t(i));
  const double expose_s = Since(start) / renders;
  std::printf("renderer, 2048 x 2048 card of 4 measured materials: %.3f s per pose\n", render_s);
  std::printf("sensor model (shot + read noise, quantisation), per frame: %.3f s\n\n", expose_s);

  std::printf("%-28s %8s %8s %9s %11s %9s %9s\n", "stream", "frames", "fps", "MB/s", "incomplete",
              "missing", "resent");
  for (bool noise : {true, false}) {
    sim::SimCameraOptions o;
    o.sensor.noise = noise;
    sim::SimGigECamera sim(
        scene, model, [&] { return view; }, o);
    AravisCameraOptions co;
    co.id = sim.address();
    AravisCamera camera(co);
    CameraSettings s;
    s.pixel_format = PixelFormat::kMono16;
    s.width = s.height = size;
    s.exposure_us = 10000;
    camera.Apply(s);
    camera.Grab();  // the first frame renders the pose
    start = Clock::now();
    for (int i = 0; i < frames; ++i) camera.Grab();
    const double seconds = Since(start);
    const StreamStatistics st = camera.Statistics();
    const double mb = double(frames) * size * size * 2 / 1e6;
    std::printf("%-28s %8d %8.2f %9.1f %11llu %9llu %9llu\n",
                noise ? "Mono16, sensor noise on" : "Mono16, noise off (transfer)", frames,
                frames / seconds, mb / seconds, (unsigned long long)st.incomplete,
                (unsigned long long)st.missing_packets, (unsigned long long)st.resent_packets);
  }
  std::printf(
      "\n(software-triggered, one frame at a time: each frame is exposed by the simulated "
      "sensor in the camera's thread, then sent)\n");
  return 0;
}
