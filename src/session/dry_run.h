// What acqd checks and shows before a session runs (issues 8, 22): every input the run will
// read, read now (the basis, the output folder, the lens model's name, a camera model calibrated
// before), and `--dry-run`'s schedule: the collision-checked visiting order, the steps with
// their placements, and the estimated capture time.
#pragma once

#include <string>

#include "acq/plan.h"

namespace acq {

// Throws UserError naming the plan's key and the fix.
void CheckSessionInputs(const Plan& plan);

// The schedule `acqd --dry-run` prints.
std::string DryRunText(const Plan& plan);

}  // namespace acq
