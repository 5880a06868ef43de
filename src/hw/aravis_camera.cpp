#include "hw/aravis_camera.h"

#include <arv.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <utility>

#include "core/error.h"

namespace acq {
namespace {

// Our formats and Aravis's codes for them (the GenICam PFNC values).
constexpr std::pair<PixelFormat, ArvPixelFormat> kArvFormats[] = {
    {PixelFormat::kMono8, ARV_PIXEL_FORMAT_MONO_8},
    {PixelFormat::kMono12, ARV_PIXEL_FORMAT_MONO_12},
    {PixelFormat::kMono16, ARV_PIXEL_FORMAT_MONO_16},
    {PixelFormat::kBayerRG8, ARV_PIXEL_FORMAT_BAYER_RG_8},
    {PixelFormat::kBayerRG12, ARV_PIXEL_FORMAT_BAYER_RG_12},
    {PixelFormat::kBayerRG16, ARV_PIXEL_FORMAT_BAYER_RG_16},
    {PixelFormat::kBayerGR8, ARV_PIXEL_FORMAT_BAYER_GR_8},
    {PixelFormat::kBayerGR12, ARV_PIXEL_FORMAT_BAYER_GR_12},
    {PixelFormat::kBayerGR16, ARV_PIXEL_FORMAT_BAYER_GR_16},
    {PixelFormat::kBayerGB8, ARV_PIXEL_FORMAT_BAYER_GB_8},
    {PixelFormat::kBayerGB12, ARV_PIXEL_FORMAT_BAYER_GB_12},
    {PixelFormat::kBayerGB16, ARV_PIXEL_FORMAT_BAYER_GB_16},
    {PixelFormat::kBayerBG8, ARV_PIXEL_FORMAT_BAYER_BG_8},
    {PixelFormat::kBayerBG12, ARV_PIXEL_FORMAT_BAYER_BG_12},
    {PixelFormat::kBayerBG16, ARV_PIXEL_FORMAT_BAYER_BG_16},
};

ArvPixelFormat ToArv(PixelFormat f) {
  return ArvPixelFormat(PfncCode(f));
}

// Takes the GError's message and frees it.
std::string Message(GError** error) {
  std::string m = *error ? (*error)->message : "unknown error";
  g_clear_error(error);
  return m;
}

const char* StatusName(ArvBufferStatus s) {
  switch (s) {
    case ARV_BUFFER_STATUS_MISSING_PACKETS:
      return "missing packets";
    case ARV_BUFFER_STATUS_TIMEOUT:
      return "timed out";
    case ARV_BUFFER_STATUS_SIZE_MISMATCH:
      return "size mismatch";
    case ARV_BUFFER_STATUS_WRONG_PACKET_ID:
      return "wrong packet id";
    case ARV_BUFFER_STATUS_ABORTED:
      return "aborted";
    default:
      return "failed";
  }
}

}  // namespace

std::uint32_t PfncCode(PixelFormat format) {
  for (const auto& [ours, arv] : kArvFormats)
    if (ours == format) return arv;
  throw std::logic_error("PixelFormat missing from kArvFormats");
}

std::optional<PixelFormat> FormatOfPfncCode(std::uint32_t code) {
  for (const auto& [ours, arv] : kArvFormats)
    if (arv == code) return ours;
  return std::nullopt;
}

AravisCamera::AravisCamera(AravisCameraOptions options) : options_(std::move(options)) {
  const std::string why = Open();
  if (!why.empty())
    throw UserError("camera " + options_.id, why,
                    "check its power and network link; `arv-tool-0.8` lists the cameras Aravis "
                    "sees and their ids");
  StartStream();
}

AravisCamera::~AravisCamera() {
  Close();
}

std::string AravisCamera::Describe() const {
  return model_.empty() ? options_.id : model_;
}

std::string AravisCamera::Open() {
  GError* error = nullptr;
  camera_ = arv_camera_new(options_.id.c_str(), &error);
  if (!camera_) return "not found or not answering: " + Message(&error);
  const char* vendor = arv_camera_get_vendor_name(camera_, nullptr);
  const char* model = arv_camera_get_model_name(camera_, nullptr);
  const char* serial = arv_camera_get_device_serial_number(camera_, nullptr);
  model_ = std::string(vendor ? vendor : "?") + " " + (model ? model : "?") + " " +
           (serial ? serial : "?") + " (" + options_.id + ")";
  if (arv_camera_is_gv_device(camera_) && !options_.packet_socket)
    arv_camera_gv_set_stream_options(camera_, ARV_GV_STREAM_OPTION_PACKET_SOCKET_DISABLED);
  arv_camera_set_acquisition_mode(camera_, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
  if (!error) arv_camera_set_trigger(camera_, "Software", &error);
  if (error) {
    const std::string why = "cannot set software-triggered acquisition: " + Message(&error);
    g_clear_object(&camera_);
    return why;
  }
  return {};
}

void AravisCamera::Close() {
  StopStream();
  if (camera_) g_clear_object(&camera_);
}

void AravisCamera::StartStream() {
  GError* error = nullptr;
  const guint payload = arv_camera_get_payload(camera_, &error);
  if (error)
    throw UserError("camera " + Describe(), "cannot read the payload size: " + Message(&error));
  stream_ = arv_camera_create_stream(camera_, nullptr, nullptr, &error);
  if (!stream_)
    throw UserError("camera " + Describe(), "cannot open its stream: " + Message(&error),
                    "is another program streaming from it?");
  if (ARV_IS_GV_STREAM(stream_))
    g_object_set(stream_, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED, "socket-buffer-size",
                 options_.socket_buffer_bytes, "packet-resend",
                 options_.packet_resend ? ARV_GV_STREAM_PACKET_RESEND_ALWAYS
                                        : ARV_GV_STREAM_PACKET_RESEND_NEVER,
                 nullptr);
  // The pool: enough buffers that the stream never starves while the worker copies one out,
  // bounded by the memory a frame size implies.
  const std::size_t buffers =
      std::clamp<std::size_t>(options_.pool_bytes / std::max<guint>(payload, 1), 3, 16);
  for (std::size_t i = 0; i < buffers; ++i)
    arv_stream_push_buffer(stream_, arv_buffer_new(payload, nullptr));
  arv_camera_start_acquisition(camera_, &error);
  if (error)
    throw UserError("camera " + Describe(), "cannot start acquisition: " + Message(&error));
  stop_worker_ = false;
  worker_ = std::thread([this] { Work(); });
}

void AravisCamera::StopStream() {
  if (worker_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_worker_ = true;
    }
    worker_.join();
  }
  if (!stream_) return;
  if (camera_) arv_camera_stop_acquisition(camera_, nullptr);  // fails harmlessly when gone
  {
    // The stream's packet counts die with it: keep them.
    std::lock_guard<std::mutex> lock(mutex_);
    AddPacketCounts(&stats_);
  }
  g_clear_object(&stream_);
  std::lock_guard<std::mutex> lock(mutex_);
  deliveries_.clear();
}

void AravisCamera::Work() {
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_worker_) return;
    }
    ArvBuffer* buffer = arv_stream_timeout_pop_buffer(stream_, 100000);  // 100 ms, to see stop
    if (!buffer) continue;
    Delivery d;
    const ArvBufferStatus status = arv_buffer_get_status(buffer);
    if (status == ARV_BUFFER_STATUS_SUCCESS) {
      std::size_t size = 0;
      const auto* data = static_cast<const std::uint8_t*>(arv_buffer_get_data(buffer, &size));
      Frame& f = d.frame;
      f.width = arv_buffer_get_image_width(buffer);
      f.height = arv_buffer_get_image_height(buffer);
      // A format we did not ask for is a short frame below: never read as another's counts.
      const std::optional<PixelFormat> format =
          FormatOfPfncCode(arv_buffer_get_image_pixel_format(buffer));
      f.pixel_format = format.value_or(PixelFormat::kMono16);
      f.frame_id = arv_buffer_get_frame_id(buffer);
      f.timestamp_ns = arv_buffer_get_timestamp(buffer);
      const std::size_t n = std::size_t(f.width) * std::size_t(f.height);
      const std::size_t bytes = f.MaxValue() == 255 ? 1 : 2;
      if (format && size >= n * bytes) {
        f.pixels.resize(n);
        if (bytes == 1)
          std::copy(data, data + n, f.pixels.begin());
        else
          std::memcpy(f.pixels.data(), data, n * 2);  // little-endian, as GigE Vision sends
        d.complete = true;
      } else {
        d.why = format ? "short frame" : "a pixel format the driver does not take";
      }
    } else {
      d.why = StatusName(status);
    }
    arv_stream_push_buffer(stream_, buffer);  // straight back: Aravis never waits for us
    std::lock_guard<std::mutex> lock(mutex_);
    if (d.complete) {
      d.frame.exposure_us = settings_.exposure_us;
      d.frame.gain_db = settings_.gain_db;
    }
    deliveries_.push_back(std::move(d));
    delivered_.notify_all();
  }
}

void AravisCamera::Apply(const CameraSettings& settings) {
  settings.Check("camera settings");
  {
    std::lock_guard<std::mutex> lock(mutex_);  // the worker stamps frames with settings_
    settings_ = settings;
  }
  have_settings_ = true;
  ApplyToDevice();
}

std::vector<std::string> AravisCamera::OfferedPixelFormats() {
  GError* error = nullptr;
  guint n = 0;
  const char** names = arv_camera_dup_available_pixel_formats_as_strings(camera_, &n, &error);
  if (error)
    throw UserError("camera " + Describe(),
                    "cannot read the pixel formats it offers: " + Message(&error));
  std::vector<std::string> out(names, names + n);
  g_free(names);
  return out;
}

void AravisCamera::RefuseFormatNotOffered(PixelFormat format) {
  const std::vector<std::string> offered = OfferedPixelFormats();
  if (std::find(offered.begin(), offered.end(), PixelFormatName(format)) != offered.end()) return;
  std::string list;
  for (const std::string& name : offered) list += (list.empty() ? "" : ", ") + name;
  throw UserError("camera " + Describe(),
                  std::string("does not offer the pixel format ") + PixelFormatName(format) +
                      " (it offers " + list + ")",
                  "name one of those in the plan's camera.pixel_format");
}

void AravisCamera::ApplyToDevice() {
  GError* error = nullptr;
  const std::string where = "camera " + Describe();
  auto check = [&](const std::string& what) {
    if (error) throw UserError(where, "cannot set " + what + ": " + Message(&error));
  };
  // The region and the pixel format change the payload: the stream is rebuilt for them only,
  // not for an exposure bracket.
  const bool restream = !stream_ || settings_.pixel_format != streamed_format_ ||
                        settings_.width != streamed_width_ || settings_.height != streamed_height_;
  if (restream) StopStream();
  if (restream && settings_.width > 0) {
    arv_camera_set_region(camera_, 0, 0, settings_.width, settings_.height, &error);
    check("the region " + std::to_string(settings_.width) + "x" + std::to_string(settings_.height));
  }
  if (restream) {
    RefuseFormatNotOffered(settings_.pixel_format);
    arv_camera_set_pixel_format(camera_, ToArv(settings_.pixel_format), &error);
    check(std::string("the pixel format ") + PixelFormatName(settings_.pixel_format));
  }
  arv_camera_set_exposure_time(camera_, settings_.exposure_us, &error);
  check("the exposure");
  arv_camera_set_gain(camera_, settings_.gain_db, &error);
  check("the gain");
  // Read back: cameras round exposures to their line time and clamp to their range.
  const double exposure = arv_camera_get_exposure_time(camera_, &error);
  check("(reading back) the exposure");
  if (std::abs(exposure - settings_.exposure_us) > std::max(1.0, 0.005 * settings_.exposure_us))
    throw UserError(where,
                    "asked for an exposure of " + std::to_string(settings_.exposure_us) +
                        " us, the camera took " + std::to_string(exposure) + " us",
                    "use an exposure within the camera's range and step");
  {
    std::lock_guard<std::mutex> lock(mutex_);
    settings_.exposure_us = exposure;  // frames carry what the camera uses
  }
  if (arv_camera_get_pixel_format(camera_, nullptr) != ToArv(settings_.pixel_format))
    throw UserError(where, std::string("the camera did not take the pixel format ") +
                               PixelFormatName(settings_.pixel_format));
  if (!restream) return;
  StartStream();
  streamed_format_ = settings_.pixel_format;
  streamed_width_ = settings_.width;
  streamed_height_ = settings_.height;
}

bool AravisCamera::StillInControl() {
  // A GigE Vision camera gives its control channel to one application (the privilege register
  // at 0x0A00 of its bootstrap memory); one that restarted, or dropped us for a missed
  // heartbeat, shows no privilege. Raw register reads bypass Aravis's feature cache. Other
  // transports (USB3 Vision) have no such register: reaching the device is all we can check.
  GError* error = nullptr;
  guint32 privilege = 0;
  const guint32 address = arv_camera_is_gv_device(camera_) ? 0x0A00 : 0;
  arv_device_read_register(arv_camera_get_device(camera_), address, &privilege, &error);
  if (error) {
    g_clear_error(&error);
    return false;
  }
  return !arv_camera_is_gv_device(camera_) || (privilege & 0x3) != 0;
}

bool AravisCamera::Reopen() {
  Close();
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(options_.reopen_timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    if (Open().empty()) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        ++stats_.reopens;
      }
      if (have_settings_)
        ApplyToDevice();
      else
        StartStream();
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return false;
}

Frame AravisCamera::Grab() {
  const std::string where = "camera " + Describe();
  std::string last_why = "none";
  auto gone = [&] {
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.1f", options_.reopen_timeout_ms / 1000.0);
    return UserError(where, "lost (" + last_why + ") and not back within " + seconds + " s",
                     "check the camera's power and network link; frames already captured are "
                     "kept, and the session resumes from here");
  };
  for (int attempt = 0; attempt <= options_.retakes; ++attempt) {
    if (attempt > 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.retakes;
    }
    if (!camera_ && !Reopen()) throw gone();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stats_.stale_discarded += deliveries_.size();  // taken before this trigger: not ours
      deliveries_.clear();
    }
    GError* error = nullptr;
    arv_camera_software_trigger(camera_, &error);
    if (error) {
      last_why = "lost control: " + Message(&error);
      if (!Reopen()) throw gone();
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    const bool got = delivered_.wait_for(lock, std::chrono::milliseconds(options_.frame_timeout_ms),
                                         [&] { return !deliveries_.empty(); });
    if (got) {
      Delivery d = std::move(deliveries_.front());
      deliveries_.pop_front();
      if (d.complete) {
        ++stats_.completed;
        return std::move(d.frame);
      }
      ++stats_.incomplete;
      last_why = d.why;
      continue;
    }
    ++stats_.incomplete;
    last_why = "no frame within " + std::to_string(options_.frame_timeout_ms) + " ms";
    lock.unlock();
    if (!StillInControl()) {
      last_why += " and the camera stopped answering or restarted";
      if (!Reopen()) throw gone();
    }
  }
  throw UserError(where,
                  "no complete frame after " + std::to_string(options_.retakes + 1) +
                      " attempts (last: " + last_why + ")",
                  "check the camera's power and link (cable, MTU, net.core.rmem_max); frames "
                  "already captured are kept");
}

StreamStatistics AravisCamera::Statistics() const {
  std::lock_guard<std::mutex> lock(mutex_);
  StreamStatistics s = stats_;
  AddPacketCounts(&s);
  return s;
}

void AravisCamera::AddPacketCounts(StreamStatistics* s) const {
  if (!stream_ || !ARV_IS_GV_STREAM(stream_)) return;  // only GigE Vision counts packets
  guint64 resent = 0, missing = 0;
  arv_gv_stream_get_statistics(ARV_GV_STREAM(stream_), &resent, &missing);
  s->resent_packets += resent;
  s->missing_packets += missing;
}

}  // namespace acq
