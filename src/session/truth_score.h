// A simulated session scored against the simulated instrument's truth (issue 21), beside the map
// scoring (acq/map_score.h): the map against the card's true materials and the calibrated
// geometry against the true camera, from the ground truth the instrument wrote into the session
// (sim/ground_truth.h) and the plan's materials. acqd scores a simulated session with it, and
// `acq session process` scores what it made of one.
#pragma once

#include <string>

#include "acq/plan.h"
#include "session/report.h"

namespace acq {

// True when `session_dir` holds the simulated card's ground truth.
bool HasGroundTruth(const std::string& session_dir);

// Fills report->score and the homogeneous figures (the map at `session_dir`/svbrdf.exr against
// the truth, per pixel also written to ground_truth/error.exr) and the calibration's error
// (report->process.calibration against the true camera at each board pose's measured arms).
// Throws UserError naming a ground-truth file that is missing or malformed.
void ScoreAgainstGroundTruth(const Plan& plan, const std::string& session_dir,
                             SessionReport* report);

}  // namespace acq
