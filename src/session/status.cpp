#include "session/status.h"

#include <nlohmann/json.hpp>

#include "core/base64.h"

namespace acq {

const char* ToString(DaemonState s) {
  switch (s) {
    case DaemonState::kStarting:
      return "starting";
    case DaemonState::kRunning:
      return "running";
    case DaemonState::kPaused:
      return "paused";
    case DaemonState::kWaiting:
      return "waiting";
    case DaemonState::kAborted:
      return "aborted";
    case DaemonState::kStopped:
      return "stopped";
    case DaemonState::kDone:
      return "done";
    case DaemonState::kFailed:
      return "failed";
    case DaemonState::kPreview:
      return "preview";
  }
  return "?";
}

std::optional<DaemonState> ParseDaemonState(const std::string& text) {
  for (DaemonState s : {DaemonState::kStarting, DaemonState::kRunning, DaemonState::kPaused,
                        DaemonState::kWaiting, DaemonState::kAborted, DaemonState::kStopped,
                        DaemonState::kDone, DaemonState::kFailed, DaemonState::kPreview})
    if (text == ToString(s)) return s;
  return std::nullopt;
}

bool IsFinal(DaemonState s) {
  return s == DaemonState::kAborted || s == DaemonState::kStopped || s == DaemonState::kDone ||
         s == DaemonState::kFailed;
}

const char* ToString(CommandKind k) {
  switch (k) {
    case CommandKind::kPause:
      return "pause";
    case CommandKind::kResume:
      return "resume";
    case CommandKind::kAbort:
      return "abort";
    case CommandKind::kConfirm:
      return "confirm";
    case CommandKind::kExposure:
      return "exposure";
  }
  return "?";
}

std::optional<CommandKind> ParseCommandKind(const std::string& text) {
  for (CommandKind k : {CommandKind::kPause, CommandKind::kResume, CommandKind::kAbort,
                        CommandKind::kConfirm, CommandKind::kExposure})
    if (text == ToString(k)) return k;
  return std::nullopt;
}

std::string SessionStatus::Json() const {
  // nlohmann writes NaN and infinities as null: the line stays valid JSON whatever is published.
  nlohmann::ordered_json j;
  j["state"] = ToString(state);
  j["step"] = step;
  j["progress"] = progress;
  j["eta_s"] = eta_s;
  j["arms_deg"] = {arms_deg[0], arms_deg[1], arms_deg[2], arms_deg[3]};
  j["frames"] = frames;
  j["incomplete_frames"] = incomplete_frames;
  j["retransmissions"] = retransmissions;
  j["prompt"] = prompt;
  j["prompt_id"] = prompt_id;
  j["last_error"] = last_error;
  j["session"] = session;
  // One line, "key": value as acqd always wrote it; nlohmann escapes every text. Invalid UTF-8
  // (a device's name, say) is replaced rather than thrown on.
  std::string line = "{";
  for (const auto& [key, value] : j.items())
    line += (line.size() > 1 ? ", " : "") + nlohmann::json(key).dump() + ": " +
            value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return line + "}";
}

std::string FramePreview::Json() const {
  nlohmann::ordered_json j;
  j["seq"] = seq;
  j["width"] = width;
  j["height"] = height;
  j["source_width"] = source_width;
  j["source_height"] = source_height;
  j["exposure_us"] = exposure_us;
  j["step"] = step;
  j["sampled"] = sampled;
  j["clipped"] = clipped;
  j["histogram"] = histogram;
  j["grey_base64"] = Base64Encode(grey);
  j["focus_width"] = focus_width;
  j["focus_height"] = focus_height;
  j["focus_base64"] = Base64Encode(focus_grey);
  j["sharpness"] = sharpness;
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace acq
