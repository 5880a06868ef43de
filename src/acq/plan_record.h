// A session remembers its plan (issue 22; docs/session-and-plan.md): at its first run the plan
// is copied into the session (plan.yaml, the files it names that are small enough, beside it in
// plan_files/) and its settings are recorded in plan_settings.tsv: every setting that changes
// what is captured, and every processing setting, the files named by their SHA-256. A later
// run (a resume) with a plan that differs in a capture setting is refused with the differences
// listed, since its frames would mix two sessions in one map; processing settings may change
// (a new k, another basis), and each change is recorded as an event in the catalog.
#pragma once

#include <string>
#include <vector>

#include "acq/plan.h"

namespace acq {

class SessionCatalog;

// In the session beside plan.yaml: the absolute folder of the plan file it was copied from (its
// relative paths are relative to that folder).
inline constexpr const char* kPlanFolderFile = "plan_folder.txt";

struct PlanSetting {
  enum class Kind { kCapture, kProcessing };
  Kind kind;
  std::string key;    // the plan's key ("camera.hdr", "directions[3]")
  std::string value;  // as text; files as "sha256:<hex> <file name>"
};

// The settings of a plan, capture then processing, in a fixed order.
std::vector<PlanSetting> PlanSettings(const Plan& plan);

struct PlanCheck {
  bool first_run = false;                       // the plan was recorded now
  std::vector<std::string> processing_changes;  // "reconstruction.k: 20 -> 10"
};

// The files and folders of a session's record of its plan (plan.yaml, plan_files/, the
// settings, the plan's folder), for a copy of the session.
std::vector<std::string> PlanRecordFiles();

// The capture settings of `plan` that differ from those `session` recorded ("key: was -> is");
// none when the session has no record. Reads and writes nothing else.
std::vector<std::string> CaptureDifferences(const Plan& plan, const std::string& session);

// "N settings<which>:" and the changes, a line each (the first 12), for an error message.
std::string ListedChanges(const std::vector<std::string>& changes, const std::string& which = "");

// What the pixels of the camera that took the session's frames integrated over (core/
// pixel_footprint.h): the simulator's pixel samples, the whole pixel of a real camera, and for a
// replay the camera of the session it replays (its recorded backend and pixel samples).
double CameraPixelSpreadPx(const Plan& plan);

// For a replay of `session`: the capture settings of `plan` that differ from those the session
// recorded and that decide which frames are asked for, in which order, at which settings (all
// but the backend, the replayed session and the simulated world); none when the session has no
// record.
std::vector<std::string> ReplayDifferences(const Plan& plan, const std::string& session);

// Records the plan into `session` at its first run, or checks it against the recorded one.
// Throws UserError listing every capture setting that differs.
PlanCheck RecordOrCheckPlan(const Plan& plan, const std::string& session, SessionCatalog& catalog);

}  // namespace acq
