#include "acq/session_repair.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "core/error.h"
#include "hw/frame_file.h"
#include "io/session_catalog.h"
#include "io/session_lock.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

struct FoundFrame {
  CatalogFrame row;
  std::string bracket;  // the frame's bracket_us attribute, "" when it has none
};

// The frame's identity from its metadata, checked against its name; "" and `why` when it is not
// a frame acqd wrote under this name.
bool ReadIdentity(const std::string& session, const std::string& relative, FoundFrame* out,
                  std::string* why) {
  std::map<std::string, std::string> attributes;
  Frame frame;
  try {
    frame = ReadFrameExr(session + "/" + relative, &attributes);
  } catch (const std::exception& e) {
    *why = std::string("not a readable frame (") + e.what() + ")";
    return false;
  }
  const auto step = attributes.find("step"), pose = attributes.find("pose");
  if (step == attributes.end() || pose == attributes.end()) {
    *why = "has no step or pose attribute";
    return false;
  }
  const std::optional<Step> step_kind = ParseStep(step->second);
  if (!step_kind) {
    *why = "its step attribute '" + step->second + "' is not a step acqd takes";
    return false;
  }
  int pose_index = -1;
  try {
    pose_index = std::stoi(pose->second);
  } catch (const std::exception&) {
  }
  const auto bracket = attributes.find("bracket_us");
  out->bracket = bracket == attributes.end() ? "" : bracket->second;
  // The catalog keys a frame by the exposure asked for (the camera reports what it set, which
  // may differ by its step): the bracket's value that names this file, else (frames written
  // before the attribute) the name's own, when it agrees with the camera's to its rounding.
  double exposure = -1;
  for (double t : ParseBracketText(out->bracket))
    if (pose_index >= 0 && FrameFileName(*step_kind, pose_index, t) == relative) exposure = t;
  if (exposure < 0) {
    const std::size_t us = relative.rfind("us.exr"), underscore = relative.rfind('_', us);
    const double named =
        us == std::string::npos || underscore == std::string::npos
            ? -1
            : std::atof(relative.substr(underscore + 1, us - underscore - 1).c_str());
    if (std::abs(named - frame.exposure_us) <= 1.5) exposure = named;
  }
  if (pose_index < 0 || exposure < 0 ||
      FrameFileName(*step_kind, pose_index, exposure) != relative) {
    *why = "its metadata (step " + step->second + ", pose " + pose->second + ", exposure " +
           std::to_string(frame.exposure_us) + " us) does not match its name";
    return false;
  }
  out->row = {*step_kind, pose_index, exposure, relative, "", 0};
  return true;
}

}  // namespace

SessionRepairReport RepairSessionCatalog(const std::string& session) {
  if (!fs::is_directory(fs::path(session) / "frames"))
    throw UserError(session, "not a session directory (no frames/ folder)",
                    "give the directory acqd wrote the session into (the plan's output)");
  const SessionLock lock(session, "acq session repair");
  SessionCatalog catalog(session);
  SessionRepairReport report;
  report.already_recorded = int(catalog.Frames().size());
  // Pose -> the frames found there, to restore decisions once all are recorded.
  std::map<std::pair<Step, int>, std::vector<FoundFrame>> poses;
  for (const std::string& relative : catalog.UnrecordedFrames()) {
    FoundFrame found;
    std::string why;
    if (!ReadIdentity(session, relative, &found, &why)) {
      report.skipped.push_back(relative + ": " + why);
      continue;
    }
    catalog.RecordFrame(found.row);
    ++report.recorded;
    poses[{found.row.step, found.row.pose}].push_back(found);
  }
  for (const auto& [pose, frames] : poses) {
    const std::string key = BracketDecisionKey(pose.first, pose.second);
    if (!catalog.Decision(key).empty()) continue;
    std::string bracket = frames.front().bracket;
    if (bracket.empty()) {
      std::vector<double> exposures;
      for (const FoundFrame& f : frames) exposures.push_back(f.row.exposure_us);
      std::sort(exposures.begin(), exposures.end());
      bracket = BracketText(exposures);
      ++report.decisions_inferred;
    }
    catalog.RecordDecision(key, bracket);
    ++report.decisions_restored;
  }
  catalog.Event("warning", "catalog repaired: " + std::to_string(report.recorded) +
                               " frames recorded from their metadata, " +
                               std::to_string(report.skipped.size()) + " files skipped");
  return report;
}

}  // namespace acq
