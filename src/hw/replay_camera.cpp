#include "hw/replay_camera.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "hw/frame_file.h"
#include "io/session_catalog.h"

namespace acq {

ReplayCamera::ReplayCamera(const std::string& session) {
  namespace fs = std::filesystem;
  folder_ = fs::is_directory(fs::path(session) / "frames") ? (fs::path(session) / "frames").string()
                                                           : session;
  if (fs::is_regular_file(fs::path(session) / "catalog.sqlite")) {
    // A session: its frames in the order they were taken (the catalog's), which is the order a
    // sequencer running the same plan asks for them.
    SessionCatalog catalog(session);
    for (const CatalogFrame& f : catalog.Frames())
      files_.push_back((fs::path(session) / f.path).string());
  } else {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder_, ec))
      if (entry.path().extension() == ".exr") files_.push_back(entry.path().string());
    if (ec) throw UserError(session, "cannot be read: " + ec.message(), "give a session directory");
    std::sort(files_.begin(), files_.end());
  }
  if (files_.empty())
    throw UserError(session, "has no frames to replay (no .exr in " + folder_ + ")",
                    "give the directory of a recorded session");
}

void ReplayCamera::Apply(const CameraSettings& settings) {
  settings.Check("camera settings");
  settings_ = settings;
  have_settings_ = true;
}

Frame ReplayCamera::Grab() {
  if (next_ >= files_.size())
    throw UserError(Describe(), "all " + std::to_string(files_.size()) + " frames were served",
                    "the session being replayed asks for more frames than were recorded; replay "
                    "it with the plan it was recorded with");
  const std::string& path = files_[next_];
  Frame f = ReadFrameExr(path);
  if (have_settings_) {
    const bool same_exposure =
        std::abs(f.exposure_us - settings_.exposure_us) <= std::max(1.0, 0.005 * f.exposure_us);
    if (!same_exposure || f.pixel_format != settings_.pixel_format ||
        std::abs(f.gain_db - settings_.gain_db) > 0.01)
      throw UserError(path,
                      "was recorded at " + std::to_string(f.exposure_us) + " us, " +
                          std::to_string(f.gain_db) + " dB, " + PixelFormatName(f.pixel_format) +
                          "; the replay asks for " + std::to_string(settings_.exposure_us) +
                          " us, " + std::to_string(settings_.gain_db) + " dB, " +
                          PixelFormatName(settings_.pixel_format),
                      "replay the session with the plan it was recorded with");
  }
  ++next_;
  ++stats_.completed;
  return f;
}

}  // namespace acq
