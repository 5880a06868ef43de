// The camera path end to end: our AravisCamera driver against the simulated camera, a real GigE
// Vision device (Aravis's fake camera) on a loopback address whose frames our renderer fills.
// Run inside tests/run_in_netns.sh (meson does), which gives the camera its own 127.0.0.N.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "acq/hdr.h"
#include "calib/synthetic_board.h"
#include "core/angles.h"
#include "core/error.h"
#include "hw/aravis_camera.h"
#include "hw/frame_file.h"
#include "hw/protocol_gantry.h"
#include "hw/replay_camera.h"
#include "io/float_planes_exr.h"
#include "sim/ground_truth.h"
#include "sim/relief.h"
#include "sim/sim_gige_camera.h"
#include "sim_gantry_link.h"
#include "test_helpers.h"

using namespace acq;

namespace {

// A small pinhole camera 500 mm above a Spectralon board, light at 45 degrees: frames of a
// few hundred kilobytes keep the loopback transfer far from any buffer limit.
calib::CameraModel SmallCamera() {
  return calib::CameraModel("LENSMODEL_PINHOLE", {400, 400, 159.5, 119.5}, 320, 240);
}

sim::SimView OverheadView() {
  sim::SimView v;
  v.cam_from_sample = calib::CamFromSampleLookingAtCentre({0, 0, 500});
  v.light.position_mm = {400, 0, 400};
  v.light.intensity = 2e5;
  return v;
}

sim::RenderScene Spectralon() {
  sim::RenderScene s;
  s.kind = sim::RenderScene::Kind::kSpectralon;
  s.sample_size_mm = 200;
  return s;
}

AravisCameraOptions SimCameraId(const sim::SimGigECamera& cam) {
  AravisCameraOptions o;
  o.id = cam.address();
  o.frame_timeout_ms = 1000;
  return o;
}

CameraSettings Settings(PixelFormat f, double exposure_us) {
  CameraSettings s;
  s.pixel_format = f;
  s.exposure_us = exposure_us;
  s.width = 320;
  s.height = 240;
  return s;
}

}  // namespace

TEST_CASE("camera: frames through Aravis equal what the renderer produced", "[camera]") {
  sim::SimGigECamera sim(Spectralon(), SmallCamera(), OverheadView, {});
  AravisCamera camera(SimCameraId(sim));
  for (PixelFormat f : {PixelFormat::kMono16, PixelFormat::kMono12, PixelFormat::kMono8}) {
    camera.Apply(Settings(f, 2000));
    const Frame frame = camera.Grab();
    const sim::ServedFrame served = sim.LastServed();
    INFO(PixelFormatName(f));
    REQUIRE(frame.width == 320);
    REQUIRE(frame.height == 240);
    CHECK(frame.pixel_format == f);
    CHECK(served.max_dn == MaxValue(f));
    CHECK(frame.exposure_us == Approx(2000));
    CHECK(served.exposure_us == Approx(2000));
    REQUIRE(frame.pixels == served.counts);  // pixel for pixel
  }
  // Rebuilding the stream for a new pixel format now and then loses the first frame's tail on
  // this loopback (Aravis reports a timeout with missing packets); the driver retakes it, which
  // is the behaviour under test: whatever is incomplete is retaken, never returned.
  const StreamStatistics s = camera.Statistics();
  CHECK(s.completed == 3);
  CHECK(s.retakes == s.incomplete);
}

// A seeded simulation reproduces its captures frame for frame even where the machine's load
// made the driver take a frame again: a frame's noise follows the seed, the view and the
// settings, not how many frames came before.
TEST_CASE("sim camera: a frame taken again is the same frame and shifts no later one", "[camera]") {
  // The frames served at these exposures in turn; a run in which the loopback itself lost a
  // frame's tail (the driver took it again, out of the test's control) is run again.
  auto grab = [](std::uint64_t seed, const std::vector<double>& exposures) {
    sim::SimCameraOptions options;
    options.seed = seed;
    for (int attempt = 0;; ++attempt) {
      sim::SimGigECamera sim(Spectralon(), SmallCamera(), OverheadView, options);
      AravisCamera camera(SimCameraId(sim));
      std::vector<std::vector<std::uint16_t>> frames;
      for (double e : exposures) {
        camera.Apply(Settings(PixelFormat::kMono16, e));
        frames.push_back(camera.Grab().pixels);
      }
      if (camera.Statistics().incomplete == 0 || attempt == 4) return frames;
    }
  };
  const auto plain = grab(1, {1500, 2000});
  const auto retaken = grab(1, {1500, 1500, 2000});  // the first 1500 as if it arrived incomplete
  CHECK(retaken[1] == plain[0]);
  CHECK(retaken[2] == plain[1]);
  // The noise is there and seeded: another seed, another frame (76,800 pixels).
  CHECK(grab(2, {1500})[0] != plain[0]);
}

TEST_CASE("renderer: a Lambertian patch gives the radiance and counts computed by hand",
          "[camera][renderer]") {
  // Spectralon (albedo 0.99) 500 mm below a pinhole camera (f = 400 px, centre (159.5, 119.5)),
  // light of intensity 2e5 at (400, 0, 400) mm. At the sample centre: d^2 = 320000 mm^2,
  // cos(theta_i) = 400 / sqrt(320000) = 0.70711, so L = 0.99 * 2e5 * 0.70711 / (pi * 320000)
  // = 0.139262. A pixel 40 px right of the centre looks at x = 500 * 40 / 400 = 50 mm (the
  // camera's x is the sample's x, CamFromSampleLookingAtCentre): d^2 = 350^2 + 400^2 = 282500,
  // cos = 400 / sqrt(282500) = 0.75259, L = 0.99 * 2e5 * 0.75259 / (pi * 282500) = 0.167906.
  const sim::RadianceImage r = sim::RenderRadiance(
      Spectralon(), SmallCamera(), OverheadView().cam_from_sample, OverheadView().light, 1);
  auto at = [&](double x, double y) {  // bilinear: the hand values are at pixel centres' corners
    const int x0 = int(x), y0 = int(y);
    const double fx = x - x0, fy = y - y0;
    auto v = [&](int i, int j) { return double(r.rgb[3 * (std::size_t(j) * 320 + i) + 1]); };
    return (1 - fy) * ((1 - fx) * v(x0, y0) + fx * v(x0 + 1, y0)) +
           fy * ((1 - fx) * v(x0, y0 + 1) + fx * v(x0 + 1, y0 + 1));
  };
  // 1e-3 relative: the radiance varies by ~0.3% per pixel here, and bilinear interpolation of
  // that smooth field over half a pixel is good to a few 1e-5; float storage to 1e-7.
  CHECK(at(159.5, 119.5) == Approx(0.139262).epsilon(1e-3));
  const double x = 159.5 + 40;
  CHECK(std::abs(at(x, 119.5) - 0.167906) / 0.167906 < 1e-3);
  // Without noise the sensor is exact: counts = L * t * quantum_scale * max / full_well.
  sim::SensorModel sensor;
  sensor.noise = false;
  const std::vector<std::uint16_t> counts =
      sim::Expose({0.139262f}, 50000, 0, 65535, sensor, 1);  // 6963 e- of 20000
  CHECK(counts[0] == std::uint16_t(std::lround(0.139262f * 50000.0 * 65535 / 20000)));
  const std::vector<std::uint16_t> saturated = sim::Expose({1.0f}, 50000, 0, 65535, sensor, 1);
  CHECK(saturated[0] == 65535);  // 50000 e- clip at the full well
}

TEST_CASE("renderer: a pixel integrates over its area when asked", "[camera][renderer]") {
  // The Spectralon 201 mm across under the camera above: its left edge, x = -100.5 mm, lies at
  // imager x = 159.5 - 100.5 * 400 / 500 = 79.1, inside pixel 79 (78.5 to 79.5), whose centre
  // sees the cloth. Over 4 x 4 points, two columns of four (79.125, 79.375) see the Spectralon.
  sim::RenderScene scene = Spectralon();
  scene.sample_size_mm = 201;
  const auto render = [&](int samples) {
    scene.pixel_samples = samples;
    return sim::RenderRadiance(scene, SmallCamera(), OverheadView().cam_from_sample,
                               OverheadView().light, 1);
  };
  const sim::RadianceImage point = render(1), area = render(4);
  auto at = [](const sim::RadianceImage& r, int x, int y) {
    return double(r.rgb[3 * (std::size_t(y) * 320 + x) + 1]);
  };
  // Inside the board the radiance is smooth (0.3% a pixel, nearly linear), so a pixel's mean is
  // its centre's to well under 1e-4.
  CHECK(at(area, 159, 119) == Approx(at(point, 159, 119)).epsilon(1e-4));
  // The edge's pixel: its centre sees the cloth (albedo 0.02), its area half cloth and half
  // board. Its neighbours' values stand for each (they differ from it by 0.3% in geometry);
  // 2% covers that and the float storage.
  const double cloth = at(point, 78, 119), board = at(point, 80, 119);
  CHECK(at(point, 79, 119) == Approx(cloth).epsilon(0.02));
  CHECK(at(area, 79, 119) == Approx((cloth + board) / 2).epsilon(0.02));
}

TEST_CASE("camera: Aravis's own arv-tool lists and controls the simulated camera", "[camera]") {
  sim::SimGigECamera sim(Spectralon(), SmallCamera(), OverheadView, {});
  auto run = [](const std::string& command) {
    std::string out;
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    REQUIRE(p);
    char line[512];
    while (fgets(line, sizeof line, p)) out += line;
    pclose(p);
    return out;
  };
  const std::string list = run("arv-tool-0.8");  // discovery, as a user would list cameras
  INFO(list);
  CHECK(list.find("Aravis-Fake-ACQSIM01 (127.0.0.2)") != std::string::npos);
  const std::string set = run("arv-tool-0.8 -a " + sim.address() +
                              " control ExposureTime=3000 Gain=6 PixelFormat=Mono12");
  INFO(set);
  CHECK(set.find("ExposureTime = 3000") != std::string::npos);
  // What arv-tool set is what the camera then uses.
  AravisCameraOptions o = SimCameraId(sim);
  AravisCamera camera(o);
  CameraSettings mine = Settings(PixelFormat::kMono16, 1500);
  camera.Apply(mine);
  camera.Grab();
  CHECK(sim.LastServed().exposure_us == Approx(1500));
  const std::string get =
      run("arv-tool-0.8 -a " + sim.address() + " control ExposureTime PixelFormat");
  INFO(get);
  CHECK(get.find("ExposureTime = 1500") != std::string::npos);
  CHECK(get.find("Mono16") != std::string::npos);
}

TEST_CASE("camera: with packets lost, every frame returned is whole and exact", "[camera]") {
  sim::SimGigECamera sim(Spectralon(), SmallCamera(), OverheadView, {});
  AravisCameraOptions o = SimCameraId(sim);
  o.packet_resend = false;  // the fake camera does not answer resend requests anyway
  o.retakes = 40;           // 1% of ~110 packets lost: a frame is whole with p = 0.99^110 = 0.33,
                            // so 41 failures in a row have p = 0.67^41 < 1e-7
  {  // one controller at a time: GigE Vision gives control to one application
    AravisCamera camera(o);
    camera.Apply(Settings(PixelFormat::kMono16, 2000));
    // Set once the camera is open: the fake camera loses control packets at the same ratio,
    // which Aravis's control channel retries.
    sim.SetLostPacketRatio(0.01);
    for (int i = 0; i < 8; ++i) {  // all 8 whole at the first try: p = 0.33^8 < 2e-4
      const Frame f = camera.Grab();
      REQUIRE(f.pixels == sim.LastServed().counts);
    }
    const StreamStatistics s = camera.Statistics();
    CHECK(s.completed == 8);
    CHECK(s.incomplete > 0);  // it did happen, and was retaken
    CHECK(s.retakes == s.incomplete);
  }
  // Every frame lost: the driver gives up with a clear error instead of returning one.
  o.retakes = 2;
  sim.SetLostPacketRatio(0);
  AravisCamera hopeless(o);
  hopeless.Apply(Settings(PixelFormat::kMono16, 2000));
  sim.SetLostPacketRatio(0.5);  // (set before opening, it also loses the control packets)
  CHECK_THROWS_WITH(hopeless.Grab(), Catch::Contains("no complete frame after 3 attempts") &&
                                         Catch::Contains("net.core.rmem_max"));
}

TEST_CASE(
    "camera: a camera that vanishes mid-bracket is reopened and the frame retaken; one "
    "that stays away fails clearly",
    "[camera]") {
  sim::SimGigECamera sim(Spectralon(), SmallCamera(), OverheadView, {});
  AravisCameraOptions o = SimCameraId(sim);
  o.frame_timeout_ms = 500;
  o.reopen_timeout_ms = 4000;
  AravisCamera camera(o);
  CameraSettings s = Settings(PixelFormat::kMono16, 1000);
  std::vector<Frame> bracket;
  s.exposure_us = 1000;
  camera.Apply(s);
  bracket.push_back(camera.Grab());
  // Power blinks between the first and the second exposure, and comes back 1.5 s later with
  // its power-on settings (Mono8, its own exposure): the driver must set ours again.
  sim.Disappear();
  std::thread power([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    sim.Reappear();
  });
  s.exposure_us = 4000;
  try {
    camera.Apply(s);  // may fail while the camera is away...
  } catch (const UserError&) {
  }
  Frame second;
  std::string error;
  try {
    second = camera.Grab();  // ...the grab reopens, re-applies and retakes
  } catch (const std::exception& e) {
    error = e.what();
  }
  power.join();
  REQUIRE(error == "");
  const sim::ServedFrame served = sim.LastServed();
  CHECK(second.pixels == served.counts);
  CHECK(served.exposure_us == Approx(4000));
  CHECK(second.exposure_us == Approx(4000));
  CHECK(served.max_dn == 65535);  // Mono16 again, not the power-on Mono8
  CHECK(camera.Statistics().reopens >= 1);
  // The merge gets whole frames at the exposures they claim: the two agree on the radiance.
  bracket.push_back(second);
  const HdrImage merged = MergeBracket(bracket, {});
  // A 20 x 20 patch at the centre of the Spectralon: ~140 and ~560 electrons per pixel, so the
  // ratio of the patch means has ~0.5% shot noise; 3% is 6 sigma.
  double sum[2] = {0, 0};
  for (int y = 110; y < 130; ++y)
    for (int x = 150; x < 170; ++x)
      for (int k = 0; k < 2; ++k)
        sum[k] += bracket[std::size_t(k)].pixels[std::size_t(y) * 320 + x];
  CHECK(sum[1] / sum[0] == Approx(4).epsilon(0.03));
  CHECK(merged.flag[120 * 320 + 160] == kHdrOk);

  sim.Disappear();  // and now for good
  const auto start = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(camera.Grab(), Catch::Contains("lost (") &&
                                       Catch::Contains("not back within 4.0 s") &&
                                       Catch::Contains("frames already captured are kept"));
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 30);
}

// One row of radiance exposed as the simulated sensor would (16 bits), at each exposure from
// `shortest` in 2-stop steps up to `longest`; each frame seeded by its exposure.
std::vector<Frame> ExposeRow(const std::vector<float>& radiance, const sim::SensorModel& sensor,
                             double shortest, double longest) {
  std::vector<Frame> frames;
  for (double t = shortest; t <= longest; t *= 4) {
    Frame f;
    f.width = int(radiance.size());
    f.height = 1;
    f.exposure_us = t;
    f.pixels = sim::Expose(radiance, t, 0, 65535, sensor, std::uint64_t(t));
    frames.push_back(std::move(f));
  }
  return frames;
}

TEST_CASE("hdr: a bracket recovers a 1e5:1 radiance range", "[hdr]") {
  // A ramp of radiance over five decades, exposed as the simulated sensor would (shot and read
  // noise, 16 bits, full well 20000 e-), in a bracket of 2-stop steps from 10 us to 164 ms.
  const int n = 4096;
  std::vector<float> radiance(n);
  for (int i = 0; i < n; ++i) radiance[i] = float(20.0 * std::pow(1e-5, double(i) / (n - 1)));
  sim::SensorModel sensor;
  const std::vector<Frame> frames = ExposeRow(radiance, sensor, 10, 200000);
  HdrOptions options;
  options.noise_floor_dn = 16;  // 4.9 e- at 3.28 DN/e-: just above the 4 e- read noise
  const HdrImage hdr = MergeBracket(frames, options);
  // Merged values are counts per us; the truth is radiance x quantum_scale x DN per electron.
  std::vector<double> errors;
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    REQUIRE(hdr.flag[i] == kHdrOk);
    const double truth = radiance[i] * sensor.CountsPerRadianceUs(65535);
    const double e = std::abs(hdr.radiance[i] - truth) / truth;
    errors.push_back(e);
    worst = std::max(worst, e);
  }
  std::sort(errors.begin(), errors.end());
  // Tolerance: the darkest pixel (2e-4 radiance units) collects 33 e- in the 164 ms frame,
  // where shot and read noise give sqrt(33 + 16) / 33 = 21% relative (1 sigma); 4 sigma is
  // 85%. The median pixel is seen by several frames with >1000 e-: ~1%, so 3% median.
  CHECK(errors[n / 2] < 0.03);
  CHECK(worst < 0.85);
  // Saturated everywhere is flagged, not invented; a pixel in the noise floor is measured
  // (3 counts in the frame: 3 counts over its exposure), not dropped.
  Frame bright = frames.front();
  std::fill(bright.pixels.begin(), bright.pixels.end(), 65535);
  Frame dark = frames.back();
  std::fill(dark.pixels.begin(), dark.pixels.end(), 3);
  CHECK(MergeBracket({bright}, options).flag[0] == kHdrSaturated);
  const HdrImage floor = MergeBracket({dark}, options);
  CHECK(floor.flag[0] == kHdrOk);
  CHECK(floor.radiance[0] == Approx(3.0 / dark.exposure_us));
}

TEST_CASE("hdr: the dark end is not biased by a noise floor", "[hdr]") {
  // A flat dark patch, 2 e- a pixel in the longest frame against 4 e- of read noise: half its
  // values lie near zero. The merge before 2026-12-03 averaged the frames whose values lay over
  // a floor of 16 counts (4.9 e-) and dropped the rest: the kept values were the ones noise put
  // high. Averaging every frame instead lifts the mean by the clip at zero counts of each short
  // frame, scaled up by its short exposure: measured +200%. The longest frame alone is biased only
  // by its own clip at zero: E[max(0, x)] for x ~ N(2, 4.2) e- is 2.9 e-, +44%.
  const int n = 20000;
  sim::SensorModel sensor;
  const double t = 163840, electrons = 2;
  const std::vector<float> radiance(n, float(electrons / (sensor.quantum_scale * t)));
  const std::vector<Frame> frames = ExposeRow(radiance, sensor, t / 64, t);
  const HdrImage hdr = MergeBracket(frames, HdrOptions{});
  const double truth = radiance[0] * sensor.CountsPerRadianceUs(65535);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    REQUIRE(hdr.flag[std::size_t(i)] == kHdrOk);  // every pixel measured, none dropped
    sum += hdr.radiance[std::size_t(i)];
  }
  const double bias = sum / n / truth - 1;
  WARN("dark patch: merged mean " << 100 * bias << "% off the truth");
  // 44% expected from the clip at zero; 20000 pixels put the mean's own noise at 1%.
  CHECK(bias == Approx(0.44).margin(0.05));
}

TEST_CASE("replay: a recorded bracket is served again in order; other settings are refused",
          "[camera][replay]") {
  const test::TempDir tmp;
  const std::string dir = tmp / "session";
  std::filesystem::create_directories(dir + "/frames");
  std::vector<Frame> recorded;
  {
    sim::SimGigECamera sim(Spectralon(), SmallCamera(), OverheadView, {});
    AravisCamera camera(SimCameraId(sim));
    recorded = CaptureBracket(camera, Settings(PixelFormat::kMono16, 500), {500, 2000, 8000});
  }
  for (std::size_t i = 0; i < recorded.size(); ++i)
    WriteFrameExr(dir + "/frames/" + std::to_string(100 + i) + "_sample.exr", recorded[i],
                  {{"camera_theta_deg", "0"}});
  ReplayCamera replay(dir);
  const std::vector<Frame> again =
      CaptureBracket(replay, Settings(PixelFormat::kMono16, 500), {500, 2000, 8000});
  REQUIRE(again.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) {
    CHECK(again[i].pixels == recorded[i].pixels);
    CHECK(again[i].exposure_us == recorded[i].exposure_us);
    CHECK(again[i].frame_id == recorded[i].frame_id);
  }
  CHECK(MergeBracket(again, {}).radiance == MergeBracket(recorded, {}).radiance);
  CHECK_THROWS_WITH(replay.Grab(), Catch::Contains("all 3 frames were served"));
  ReplayCamera other(dir);
  CHECK_THROWS_WITH(CaptureBracket(other, Settings(PixelFormat::kMono16, 500), {1000}),
                    Catch::Contains("100_sample.exr") && Catch::Contains("was recorded at 500") &&
                        Catch::Contains("asks for 1000"));
  CHECK_THROWS_WITH(ReplayCamera("no_such_session"), Catch::Contains("no_such_session"));
}

TEST_CASE("sim camera: renders from where the simulated gantry holds the arms; automatic bracket",
          "[camera][hdr]") {
  sim::SimGantryFirmware firmware;
  test::SimGantryLink link(firmware);
  ProtocolGantry gantry(link);
  gantry.Home();
  auto view = [&] { return sim::ViewFromArms(firmware.Measured(), 500, 600, 2e5); };
  sim::SimCameraOptions options;
  options.sensor.noise = false;  // so the frame can be predicted exactly
  sim::SimGigECamera sim(Spectralon(), SmallCamera(), view, options);
  AravisCamera camera(SimCameraId(sim));
  const CameraSettings s = Settings(PixelFormat::kMono16, 3000);
  camera.Apply(s);
  const ArmAngles pose{DegToRad(50), DegToRad(40), DegToRad(20), DegToRad(-140)};
  MoveAndWait(gantry, pose, 20);
  const Frame frame = camera.Grab();
  const sim::SimView expected = sim::ViewFromArms(pose, 500, 600, 2e5);
  const std::vector<std::uint16_t> predicted = sim::Expose(
      sim::RenderRadiance(Spectralon(), SmallCamera(), expected.cam_from_sample, expected.light)
          .Channel(-1),
      3000, 0, 65535, options.sensor, 0);
  CHECK(frame.pixels == predicted);

  // The bracket chosen from the scene, on 8 bits: the Spectralon and the dark cloth around it
  // (50:1) need more than one frame to put the cloth 10x above a 2-count floor. Its shortest
  // exposure keeps every pixel below saturation; the merge leaves none saturated or dark.
  CameraSettings mono8 = Settings(PixelFormat::kMono8, 3000);
  HdrOptions hdr;
  hdr.noise_floor_dn = 2;
  const std::vector<double> bracket = ChooseBracket(camera, mono8, hdr, {});
  REQUIRE(bracket.size() >= 2);
  const std::vector<Frame> frames = CaptureBracket(camera, mono8, bracket);
  const auto brightest = *std::max_element(frames[0].pixels.begin(), frames[0].pixels.end());
  CHECK(brightest < 0.95 * 255);
  CHECK(brightest > 0.5 * 255);  // but not wastefully short: the headroom asked for is 0.8
  const HdrImage merged = MergeBracket(frames, hdr);
  CHECK(std::count(merged.flag.begin(), merged.flag.end(), kHdrSaturated) == 0);
  // The dark end: the longest frame lifts the darkest 1% to 10x the floor (2 counts); half of
  // that leaves room for the probe's noise and the 2-stop steps' rounding.
  std::vector<std::uint16_t> longest = frames.back().pixels;
  std::nth_element(longest.begin(), longest.begin() + std::ptrdiff_t(longest.size() / 100),
                   longest.end());
  WARN("darkest 1% in the longest frame: " << longest[longest.size() / 100] << " counts");
  CHECK(longest[longest.size() / 100] >= 10);

  // The ground truth beside a session: labels, names, the camera model.
  sim::RenderScene card;
  card.card = sim::MakeCardLayout(16, 8, 100, 2, 1);
  card.material_names = {"white-paint", "brass"};
  const test::TempDir tmp;
  sim::WriteGroundTruth(tmp / "ground_truth", card, SmallCamera());
  const FloatPlanes labels = ReadFloatPlanesExr(tmp / "ground_truth/ground_truth_labels.exr");
  CHECK(labels.width == 16);
  CHECK(labels.Plane("material", "labels") ==
        std::vector<float>(card.card.label.begin(), card.card.label.end()));
  CHECK(calib::CameraModel::Read(tmp / "ground_truth/camera.cameramodel").width() == 320);
  CHECK(sim::ReadGroundTruth(tmp / "ground_truth").card.normal.empty());  // flat: no normals

  // With relief, its true normals go with the labels and come back as written.
  sim::ReliefOptions relief;
  relief.slope_deg = 15;
  sim::SetNormalsFromHeight(&card.card, sim::CardRelief(card.card, relief));
  sim::WriteGroundTruth(tmp / "relief", card, SmallCamera());
  const sim::GroundTruthFiles back = sim::ReadGroundTruth(tmp / "relief");
  REQUIRE(back.card.normal.size() == card.card.normal.size());
  int tilted = 0;
  for (std::size_t i = 0; i < back.card.normal.size(); ++i) {
    CHECK((back.card.normal[i] - card.card.normal[i]).norm() < 1e-6);  // float planes, unit
    tilted += card.card.normal[i].z() < 0.999f;
  }
  CHECK(tilted > 0);
  CHECK(back.card.NormalAt({0, 0}) == back.card.normal[std::size_t(4 * 16 + 8)]);

  // A session simulated before the row rule (format 1) ran its card's rows to the sample's +y:
  // read back, every cell keeps its place on the sample, so scoring that session's map is still
  // against its own card and not its mirror image.
  FloatPlanes old = ReadFloatPlanesExr(tmp / "relief/ground_truth_labels.exr");
  const std::size_t w = std::size_t(old.width), h = std::size_t(old.height);
  for (const char* plane : {"material", "normal.x", "normal.y", "normal.z"}) {
    std::vector<float>& v = old.planes.at(plane);
    for (std::size_t r = 0; r < h / 2; ++r)  // the same cells, laid with rows to +y
      std::swap_ranges(v.begin() + long(r * w), v.begin() + long((r + 1) * w),
                       v.begin() + long((h - 1 - r) * w));
  }
  old.attributes["acqFormat"] = "acq-ground-truth-1";
  WriteFloatPlanesExr(tmp / "relief/ground_truth_labels.exr", old);
  const sim::GroundTruthFiles converted = sim::ReadGroundTruth(tmp / "relief");
  CHECK(converted.card.label == card.card.label);
  for (std::size_t i = 0; i < converted.card.normal.size(); ++i)
    CHECK((converted.card.normal[i] - card.card.normal[i]).norm() < 1e-6);
  old.attributes["acqFormat"] = "acq-ground-truth-9";
  WriteFloatPlanesExr(tmp / "relief/ground_truth_labels.exr", old);
  CHECK_THROWS_AS(sim::ReadGroundTruth(tmp / "relief"), UserError);
}
