// A capture step's poses as the processing reads them back from the session: each pose's
// bracket merged into one HDR image (written to hdr/<step>_NNN.exr), with the arm angles the
// gantry measured and the direction recorded with its frames.
#pragma once

#include <map>
#include <string>

#include "acq/hdr.h"
#include "core/gantry_geometry.h"
#include "io/session_catalog.h"

namespace acq {

struct PoseHdr {
  HdrImage hdr;
  ArmAngles arms;         // measured at the pose
  std::string direction;  // the plan's direction (file:line), as recorded with the frames
};

// "<step>_NNN": the pose's name in hdr/, correspondence/ and messages.
std::string PoseName(const std::string& step, int pose);

// Merges every pose of `step` found in the catalog (pose index -> image) and writes
// hdr/<step>_NNN.exr; adds the time taken to `*seconds`.
std::map<int, PoseHdr> MergeStep(const std::string& step, SessionCatalog& catalog, double* seconds);

}  // namespace acq
