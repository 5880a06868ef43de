// The session report (issue 8): where the time went and what came out, written as report.json
// (for programs and tests) and report.txt (for people) into the session directory.
//
// Time is split into the instrument's (motion and settling, exposure, transfer: what a faster
// daemon could not shorten), the operator's, processing (per stage), and the daemon's own
// overhead: the session's wall time less all of those (starting the devices, planning the
// visiting order, writing frames and the catalog, publishing status).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "acq/map_score.h"
#include "session/capture.h"
#include "session/process.h"

namespace acq {

struct SessionReport {
  std::string plan, backend, session;
  // The camera's colour filter (the plan's pixel format): a colour session's report has a
  // "colour" section (CIEDE2000 of the validation views and, simulated, of the diffuse colour).
  Cfa colour_filter = Cfa::kNone;
  bool colour() const { return colour_filter != Cfa::kNone; }
  // false: the session processed again by `acq session process` (no capture in this run).
  bool captured = true;
  double wall_s = 0;      // acqd's start to the report
  double planning_s = 0;  // the visiting order
  double scoring_s = 0;   // against the simulated truth (simulation only)
  CaptureReport capture;
  // Processing that ran during the capture (background.h): worker time (overlapped, so not part
  // of the breakdown), the poses it merged, and the wait for what it had left at the end.
  double background_busy_s = 0, background_wait_s = 0;
  int background_poses = 0;
  double writer_busy_s = 0;     // writing and recording the frames, off the capture's thread
  double writer_blocked_s = 0;  // the capture waiting for room in the writer's queue
  // From the last frame to the session processed (the map and its validation renders; the
  // scoring not included): what the capture's overlap with processing leaves to wait for.
  double after_capture_s = 0;
  // The camera's stream over this run: frames that arrived incomplete (and were taken again)
  // and frames retaken.
  long incomplete_frames = 0, retaken_frames = 0;
  ProcessReport process;
  // The simulated instrument only: the map against the card's true materials, and the
  // homogeneous result for the same materials and directions (Yu et al. / NJR15 evaluation).
  bool scored = false;
  MapScore score;
  double homogeneous_median_log_rmse = 0;
  std::vector<std::string> materials;        // names, in label order
  std::vector<double> homogeneous_log_rmse;  // per material (mean over its channels)
  // The calibrated geometry against the true one, as misalignment in the views: points over
  // the sample projected through both, every board pose (median and worst, pixels).
  double alignment_median_px = 0, alignment_max_px = 0;
  // The camera centre each board pose gives, against the true one, as seen from the sample
  // (degrees): why the view directions come from the camera's arm (process.h).
  double board_eye_error_median_deg = 0, board_eye_error_max_deg = 0;
  // Each validation view against the truth (truth_score.h): the true materials rendered at every
  // pixel's own directions, sampled as the capture was (acq/capture_sampling.h), against the
  // capture (the capture's noise and what its pixels saw between the map's, which at a
  // mirror-like ink's pixel-wide highlights is most of it: a floor no model can go under;
  // docs/reconstruction.md, "The files sample's view 8"), and the map's render against that
  // truth render, both at the pixels' own points (the map's error without the capture's).
  struct ValidationTruth {
    std::string name;
    double capture_delta_e2000 = 0, capture_relative_rms = 0;  // truth vs capture
    double map_delta_e2000 = 0, map_relative_rms = 0;          // map vs truth
  };
  std::vector<ValidationTruth> validation_truth;
  // The map's normals against the relief's (a simulated sample with relief only).
  std::optional<NormalScore> normals;

  double OverheadS() const;
  std::string Json() const;
  std::string Text() const;
};

// report.json and report.txt into the session directory (atomically, each).
void WriteReport(const SessionReport& report, const std::string& session_dir);

}  // namespace acq
