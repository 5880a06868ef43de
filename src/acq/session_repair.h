// `acq session repair` (issue 22): the catalog rebuilt from the frames' own metadata, for a
// session whose catalog.sqlite was deleted, emptied or lost rows (acqd refuses to resume such a
// session rather than delete the frames it no longer knows). Every frame file under frames/ that
// the catalog does not record is read; its step, pose and exposure (EXR attributes) must agree
// with its name; it is recorded with its checksum, and the automatic bracket decision of its
// pose restored from its `bracket_us` attribute (frames written before that attribute: the
// exposures found at the pose). Nothing is deleted or moved; files that are not readable frames
// are reported and left.
#pragma once

#include <string>
#include <vector>

namespace acq {

struct SessionRepairReport {
  int recorded = 0;                  // frames added to the catalog
  int already_recorded = 0;          // frames the catalog had
  int decisions_restored = 0;        // bracket decisions recorded
  int decisions_inferred = 0;        // of which from the exposures present (no attribute)
  std::vector<std::string> skipped;  // "frames/x.exr: why", left where they are
};

// Takes the session's lock (refused while an acqd runs on it). Throws UserError when `session`
// is not a session directory.
SessionRepairReport RepairSessionCatalog(const std::string& session);

}  // namespace acq
