#include "sim/sim_gige_camera.h"

#include <arv.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "calib/synthetic_board.h"
#include "core/splitmix.h"
#include "hw/aravis_camera.h"

namespace acq::sim {
namespace {

constexpr double kGainRawPerDb = 100;  // the gain register holds centi-dB

void FillCallback(ArvBuffer* buffer, void* self, guint32 exposure_us, guint32 gain,
                  ArvPixelFormat format) {
  static_cast<SimGigECamera*>(self)->Fill(buffer, exposure_us, gain, format);
}

void InsertAfter(std::string* xml, const std::string& anchor, const std::string& text) {
  const std::size_t at = xml->find(anchor);
  if (at == std::string::npos)
    throw std::runtime_error("Aravis's fake camera XML has no " + anchor +
                             "; this Aravis is not the 0.8 series the simulator was written for");
  xml->insert(at + anchor.size(), text);
}

// A well-spread 64-bit key from a sequence of values: each folded into the key so far, then
// splitmix64's finaliser.
std::uint64_t Mix(std::uint64_t h, std::uint64_t v) {
  return SplitMix64Finalise(h ^ (v + kGoldenGamma + (h << 6) + (h >> 2)));
}

std::uint64_t Mix(std::uint64_t h, double v) {
  return Mix(h, std::bit_cast<std::uint64_t>(v));
}

// A frame's noise seed: the session's seed, the view, the exposure and the gain, and nothing
// that counts frames. A seeded session then repeats frame for frame whatever frames were
// retaken: a frame the driver takes again (it arrived incomplete) is the same frame, and no later
// frame shifts. The price: frames taken at the same view and settings repeat their noise too
// (nothing in the product averages such frames; docs/camera.md).
std::uint64_t NoiseSeed(std::uint64_t seed, const SimView& v, double exposure_us, double gain_db) {
  std::uint64_t h = Mix(seed, exposure_us);
  h = Mix(h, gain_db);
  for (int i = 0; i < 3; ++i) {
    h = Mix(h, v.cam_from_sample.r[i]);
    h = Mix(h, v.cam_from_sample.t[i]);
    h = Mix(h, v.light.position_mm[i]);
    h = Mix(h, v.light.rgb[i]);
  }
  return Mix(h, v.light.intensity);
}

bool SameView(const SimView& a, const SimView& b) {
  return a.cam_from_sample.r == b.cam_from_sample.r && a.cam_from_sample.t == b.cam_from_sample.t &&
         a.light.position_mm == b.light.position_mm && a.light.intensity == b.light.intensity &&
         a.light.rgb == b.light.rgb;
}

// The formats a sensor with this filter offers: its phase (or mono) at 8, 12 and 16 bits.
std::vector<PixelFormat> OfferedFormats(Cfa cfa) {
  return {PixelFormatFor(cfa, 255), PixelFormatFor(cfa, 4095), PixelFormatFor(cfa, 65535)};
}

// The full scale of a format the camera offers; 65535 for another (a driver that set a format
// not offered is refused by the GenICam enumeration before it gets here).
int MaxDn(Cfa cfa, std::uint32_t code) {
  for (PixelFormat f : OfferedFormats(cfa))
    if (PfncCode(f) == code) return MaxValue(f);
  return 65535;
}

// Replaces the fake camera's PixelFormat entries (its four 8-bit Bayer phases, RGB8, Mono8,
// Mono16, whatever sensor it stands for) by the formats of ours.
void ReplacePixelFormatEntries(std::string* xml, Cfa cfa) {
  const std::string open = "<Enumeration Name=\"PixelFormat\" NameSpace=\"Standard\">";
  const std::size_t at = xml->find(open);
  const std::size_t end = xml->find("<pValue>PixelFormatRegister</pValue>", at);
  if (at == std::string::npos || end == std::string::npos)
    throw std::runtime_error(
        "Aravis's fake camera XML has no PixelFormat enumeration; this "
        "Aravis is not the 0.8 series the simulator was written for");
  std::string entries = "\n\t\t<DisplayName>Pixel format</DisplayName>";
  for (PixelFormat f : OfferedFormats(cfa))
    entries += std::string("\n\t\t<EnumEntry Name=\"") + PixelFormatName(f) +
               "\" NameSpace=\"Standard\">\n\t\t\t<Value>" + std::to_string(PfncCode(f)) +
               "</Value>\n\t\t</EnumEntry>";
  const std::size_t from = at + open.size();
  xml->replace(from, end - from, entries + "\n\t\t");
}

}  // namespace

std::vector<float> MosaicOf(const RadianceImage& rec709, const Eigen::Matrix3d& camera_from_rec709,
                            Cfa cfa) {
  const Eigen::Matrix3f m = camera_from_rec709.cast<float>();
  std::vector<float> out(std::size_t(rec709.width) * std::size_t(rec709.height));
#pragma omp parallel for schedule(static)
  for (int y = 0; y < rec709.height; ++y)
    for (int x = 0; x < rec709.width; ++x) {
      const std::size_t i = std::size_t(y) * rec709.width + x;
      const Eigen::Vector3f rgb(rec709.rgb[3 * i], rec709.rgb[3 * i + 1], rec709.rgb[3 * i + 2]);
      out[i] = m.row(CfaChannel(cfa, x, y)).dot(rgb);
    }
  return out;
}

Eigen::Matrix3d PlausibleCameraCrosstalk() {
  Eigen::Matrix3d m;
  m << 0.78, 0.18, 0.04,  //
      0.12, 0.76, 0.12,   //
      0.04, 0.22, 0.74;
  return m;
}

std::string SimCameraGenicamXml(Cfa cfa) {
  ArvFakeCamera* probe = arv_fake_camera_new("probe");
  std::size_t size = 0;
  const char* base = arv_fake_camera_get_genicam_xml(probe, &size);
  std::string xml(base, size);
  g_object_unref(probe);
  InsertAfter(&xml, "<pFeature>ExposureTimeAbs</pFeature>",
              "\n\t\t<pFeature>ExposureTime</pFeature>");
  InsertAfter(&xml, "<pFeature>GainRaw</pFeature>", "\n\t\t<pFeature>Gain</pFeature>");
  ReplacePixelFormatEntries(&xml, cfa);
  InsertAfter(&xml, "<!-- Analog control -->", R"(
	<Float Name="ExposureTime" NameSpace="Standard">
		<Description>Exposure duration, in microseconds (SFNC name).</Description>
		<pValue>ExposureTimeAbsConverter</pValue>
		<Min>10.0</Min>
		<Max>10000000.0</Max>
		<Unit>us</Unit>
	</Float>

	<Float Name="Gain" NameSpace="Standard">
		<Description>Gain in dB (SFNC name); the register holds centi-dB.</Description>
		<pValue>GainDbConverter</pValue>
		<Min>0.0</Min>
		<Max>24.0</Max>
		<Unit>dB</Unit>
	</Float>

	<Converter Name="GainDbConverter" NameSpace="Custom">
		<FormulaTo>FROM * 100</FormulaTo>
		<FormulaFrom>TO / 100</FormulaFrom>
		<pValue>GainRawRegister</pValue>
	</Converter>
)");
  return xml;
}

SimView ViewFromArms(const ArmAngles& arms, double camera_distance_mm, double light_distance_mm,
                     double light_intensity) {
  const DirectionPair far = DirectionsOf(arms);
  SimView v;
  v.cam_from_sample = calib::CamFromSampleLookingAtCentre(far.out * camera_distance_mm);
  v.light.position_mm = far.in * light_distance_mm;
  v.light.intensity = light_intensity;
  return v;
}

SimGigECamera::SimGigECamera(RenderScene scene, calib::CameraModel model,
                             std::function<SimView()> view, SimCameraOptions options)
    : scene_(std::move(scene)),
      model_(std::move(model)),
      view_(std::move(view)),
      options_(std::move(options)) {
  char path[] = "/tmp/acq-sim-camera-XXXXXX.xml";
  const int fd = mkstemps(path, 4);
  if (fd < 0) throw std::runtime_error("cannot write the simulated camera's GenICam file in /tmp");
  close(fd);
  genicam_path_ = path;
  std::ofstream(genicam_path_) << SimCameraGenicamXml(options_.cfa);
  Start();
}

SimGigECamera::~SimGigECamera() {
  Stop();
  std::remove(genicam_path_.c_str());
}

void SimGigECamera::Start() {
  ArvGvFakeCamera* gv = arv_gv_fake_camera_new_full(options_.address.c_str(),
                                                    options_.serial.c_str(), genicam_path_.c_str());
  if (!gv || !arv_gv_fake_camera_is_running(gv)) {
    if (gv) g_object_unref(gv);
    throw std::runtime_error("the simulated camera cannot listen on " + options_.address +
                             ": the address must be on an interface (ip addr add " +
                             options_.address + "/8 dev lo; tests/run_in_netns.sh does so)");
  }
  ArvFakeCamera* fake = arv_gv_fake_camera_get_fake_camera(gv);
  // Power-on image size: the camera model's, so a driver that sets nothing gets whole frames.
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_WIDTH, guint32(model_.width()));
  arv_fake_camera_write_register(fake, ARV_FAKE_CAMERA_REGISTER_HEIGHT, guint32(model_.height()));
  arv_fake_camera_set_fill_pattern(fake, FillCallback, this);
  if (lost_ratio_ > 0) g_object_set(gv, "gvsp-lost-ratio", lost_ratio_, nullptr);
  gv_camera_ = gv;
}

void SimGigECamera::Stop() {
  if (gv_camera_) g_object_unref(static_cast<ArvGvFakeCamera*>(gv_camera_));
  gv_camera_ = nullptr;
}

void SimGigECamera::Disappear() {
  Stop();
}

void SimGigECamera::Reappear() {
  if (!gv_camera_) Start();
}

void SimGigECamera::SetScene(RenderScene scene) {
  std::lock_guard<std::mutex> lock(mutex_);
  scene_ = std::move(scene);
  have_render_ = false;
}

void SimGigECamera::SetLostPacketRatio(double ratio) {
  lost_ratio_ = ratio;
  if (gv_camera_)
    g_object_set(static_cast<ArvGvFakeCamera*>(gv_camera_), "gvsp-lost-ratio", ratio, nullptr);
}

ServedFrame SimGigECamera::LastServed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_;
}

double SimGigECamera::last_render_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return render_seconds_;
}

std::uint64_t SimGigECamera::frames_served() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_.index;
}

void SimGigECamera::Fill(void* buffer_pointer, std::uint32_t exposure_us, std::uint32_t gain_raw,
                         std::uint32_t format) {
  auto* buffer = static_cast<ArvBuffer*>(buffer_pointer);
  // Inside the fill callback arv_buffer_get_data reports size 0: size the frame from its
  // width, height and pixel format instead.
  const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
  auto* data = static_cast<std::uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
  const SimView view = view_();
  std::lock_guard<std::mutex> lock(mutex_);
  ServedFrame frame;
  frame.index = last_.index + 1;
  frame.width = w;
  frame.height = h;
  frame.max_dn = MaxDn(options_.cfa, format);
  frame.exposure_us = exposure_us;
  frame.gain_db = gain_raw / kGainRawPerDb;
  if (w == model_.width() && h == model_.height()) {
    if (!have_render_ || !SameView(view, rendered_view_)) {
      const auto start = std::chrono::steady_clock::now();
      const RadianceImage rec709 = RenderRadiance(scene_, model_, view.cam_from_sample, view.light,
                                                  options_.ray_grid_step_px);
      radiance_ = options_.cfa == Cfa::kNone
                      ? rec709.Channel(options_.channel)
                      : MosaicOf(rec709, options_.camera_from_rec709, options_.cfa);
      render_seconds_ =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      rendered_view_ = view;
      have_render_ = true;
    }
    frame.counts =
        Expose(radiance_, frame.exposure_us, frame.gain_db, frame.max_dn, options_.sensor,
               NoiseSeed(options_.seed, view, frame.exposure_us, frame.gain_db));
  } else {
    // A region other than the camera model's: no geometry to render it with. A black frame
    // makes the mismatch obvious; the driver sets the model's size.
    frame.counts.assign(std::size_t(w) * std::size_t(h), 0);
  }
  if (frame.max_dn == 255) {
    for (std::size_t i = 0; i < frame.counts.size(); ++i) data[i] = std::uint8_t(frame.counts[i]);
  } else {
    std::memcpy(data, frame.counts.data(), frame.counts.size() * 2);  // little-endian host
  }
  last_ = std::move(frame);
}

}  // namespace acq::sim
