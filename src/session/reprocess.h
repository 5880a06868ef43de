// `acq process` (issue 21): the processing stages of a captured session run again, with
// processing settings changed, into the session or into a copy of it, never touching the frames.
// acqd runs the same ProcessSession() at the end of a capture; here it runs from the session's
// own record of its plan (plan.yaml, read relative to the folder it came from) and its catalog.
//
// Stages, in order: hdr (each pose's bracket merged), calibration (intrinsics and each pose's
// cam_from_sample from the session's boards), reconstruction (correspondence, the per-pixel
// solve, validation renders, the report). Starting at a stage re-runs it and all after it and
// reuses the outputs of the stages before: --from calibration reuses the HDR merges, --from
// reconstruction the calibration written in calibration/.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "acq/plan.h"
#include "session/process.h"

namespace acq {

enum class ProcessStage { kHdr, kCalibration, kReconstruction };
const char* ToString(ProcessStage stage);
std::optional<ProcessStage> ParseProcessStage(const std::string& text);

struct ReprocessOptions {
  std::string session;  // a captured session (acqd's output folder)
  ProcessStage from = ProcessStage::kCalibration;
  std::vector<std::string> settings;  // "reconstruction.k=10": processing settings
  std::string output;                 // empty: into `session`; else a new folder
  // Throws UserError naming the option: the session must hold a catalog and its plan; the
  // output must not exist (or be empty) and must not lie inside the session.
  void Check() const;
};

struct ReprocessResult {
  Plan plan;                                    // as processed (output: the folder written)
  std::vector<std::string> processing_changes;  // "reconstruction.k: 20 -> 10"
  ProcessReport process;
};

// Throws UserError when a setting is unknown, refers to what was captured (the settings'
// kinds are the plan record's, plan_record.h), or the session is in use (its lock).
ReprocessResult ReprocessSession(const ReprocessOptions& options);

}  // namespace acq
