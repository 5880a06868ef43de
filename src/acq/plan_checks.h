// What the dry run checks beyond the plan's own validation (issue 22): the files and folders the
// run will open, so that a plan that passes --dry-run does not fail later on them. The basis is
// opened (header, sizes, checksum) and k matched to it and to the directions; the output folder
// must be a folder that can be written, not the file system's root, a device, a system folder
// or inside the project's source tree (its out/ and build folders excepted).
#pragma once

#include "acq/plan.h"

namespace acq {

// Throws UserError naming the plan's key (file:line:column) and the fix.
void CheckPlanResources(const Plan& plan);

// The output folder rule alone (also used by `acq process -o`): `where` names the setting.
void CheckOutputFolder(const std::string& folder, const std::string& where);

}  // namespace acq
