// A GenICam camera through Aravis 0.8 (issue 6). Frames are taken one at a time by software
// trigger, so each frame starts after the settings it must use were written and read back (a
// camera that lags an exposure change by a frame in free-running mode cannot slip one in). A
// worker thread takes every buffer from Aravis's stream as it completes, copies it and gives the
// buffer straight back, so Aravis's own receiving thread never waits on us.
//
// Failures: an incomplete frame (missing packets, timeout) is counted and the frame triggered
// again, up to `retakes` times; a camera that stops answering is reopened (until
// `reopen_timeout_ms`), its settings applied again, and the frame retaken. What cannot be
// recovered throws UserError; no incomplete frame is ever returned.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "hw/camera.h"

typedef struct _ArvCamera ArvCamera;
typedef struct _ArvStream ArvStream;

namespace acq {

// A format's GenICam PFNC code, the PixelFormat register's value (Aravis's ARV_PIXEL_FORMAT_*),
// and the format of a code, nullopt for one the driver does not take.
std::uint32_t PfncCode(PixelFormat format);
std::optional<PixelFormat> FormatOfPfncCode(std::uint32_t code);

struct AravisCameraOptions {
  std::string id;  // Aravis device id ("Aravis-Fake-ACQSIM01"), serial or IP address
  int frame_timeout_ms = 3000;
  int retakes = 3;
  int reopen_timeout_ms = 5000;
  // GigE Vision on loopback or a busy host: a fixed receive buffer (the kernel caps it at
  // net.core.rmem_max) and no packet socket (which receives nothing on loopback).
  int socket_buffer_bytes = 32 << 20;
  bool packet_socket = false;
  bool packet_resend = true;
  std::size_t pool_bytes = std::size_t(256) << 20;  // buffer pool: this many bytes of frames
};

class AravisCamera : public Camera {
 public:
  explicit AravisCamera(AravisCameraOptions options);  // throws UserError when not found
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  void Apply(const CameraSettings& settings) override;
  Frame Grab() override;
  StreamStatistics Statistics() const override;
  std::string Describe() const override;

 private:
  struct Delivery {  // what the worker hands over: a complete frame or a failure
    bool complete = false;
    std::string why;
    Frame frame;
  };
  std::string Open();  // empty on success, else why
  void Close();
  void StartStream();
  void StopStream();
  void ApplyToDevice();                            // throws UserError
  std::vector<std::string> OfferedPixelFormats();  // the camera's PixelFormat entries
  // UserError naming the formats it offers when `format` is not one (before any motion: the
  // daemon applies the plan's settings at connect).
  void RefuseFormatNotOffered(PixelFormat format);
  bool Reopen();
  bool StillInControl();
  void AddPacketCounts(StreamStatistics* s) const;  // the live stream's, if GigE Vision
  void Work();

  AravisCameraOptions options_;
  CameraSettings settings_;
  bool have_settings_ = false;
  ArvCamera* camera_ = nullptr;
  ArvStream* stream_ = nullptr;
  PixelFormat streamed_format_ = PixelFormat::kMono16;  // what stream_ was built for
  int streamed_width_ = -1, streamed_height_ = -1;
  std::string model_;
  std::thread worker_;
  bool stop_worker_ = false;
  mutable std::mutex mutex_;
  std::condition_variable delivered_;
  std::deque<Delivery> deliveries_;
  StreamStatistics stats_;
};

}  // namespace acq
