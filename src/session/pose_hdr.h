// A capture step's poses as the processing reads them back from the session: each pose's
// bracket merged into one HDR image, written to hdr/<step>_NNN.exr with the arm angles the
// gantry measured and the direction recorded with its frames, and its thumbnail beside it
// (hdr_thumbnail.h). An hdr file that names exactly the
// pose's frames and is newer than all of them is read back instead of merging again: the
// merges made while the capture went on (background.h), and those of an earlier processing run.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "acq/hdr.h"
#include "core/gantry_geometry.h"
#include "io/session_catalog.h"

namespace acq {

// What the processing needs of a session's catalog, copied once: a worker thread reads this,
// never the catalog's connection.
struct SessionFrames {
  std::string dir;
  std::vector<CatalogFrame> frames;
  static SessionFrames Of(const SessionCatalog& catalog) {
    return {catalog.directory(), catalog.Frames()};
  }
  // The frames of one pose of a step, in the catalog's order.
  std::vector<CatalogFrame> OfPose(Step step, int pose) const;
};

struct PoseHdr {
  HdrImage hdr;
  ArmAngles arms;         // measured at the pose
  std::string direction;  // the plan's direction (file:line), as recorded with the frames
};

// "<step>_NNN": the pose's name in hdr/, correspondence/ and messages.
std::string PoseName(Step step, int pose);

// The merged image of one pose from its frames (merged and written, or read back when its hdr
// file is up to date); adds the time taken to `*seconds`.
PoseHdr MergePose(const std::string& dir, Step step, int pose,
                  const std::vector<CatalogFrame>& frames, double* seconds);

// Every pose of `step` in the session (pose index -> image). A pose in `merged_before` (merged
// while the capture went on) is taken from there, not merged again.
std::map<int, PoseHdr> MergeStep(Step step, const SessionFrames& session, double* seconds,
                                 std::map<std::pair<Step, int>, PoseHdr>* merged_before = nullptr);

}  // namespace acq
