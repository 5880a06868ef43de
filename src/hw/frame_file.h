// A raw camera frame as a file of the session directory (docs/session-and-plan.md):
// frames/NNN_KIND_EXP.exr, the counts as one float plane "counts" (exact up to 2^24, so every
// 16-bit count survives) and the frame's metadata as EXR string attributes (acqFormat
// "acq-frame-1", exposure_us, gain_db, pixel_format, frame_id, timestamp_ns, plus whatever the
// caller adds: arm angles, camera and gantry ids, stream statistics).
#pragma once

#include <map>
#include <string>

#include "core/gantry_geometry.h"
#include "hw/camera.h"

namespace acq {

// The arm angles recorded with a frame (attributes arms_commanded_deg, arms_measured_deg):
// light theta, light phi, camera theta, camera phi in degrees, space-separated.
std::string ArmAnglesAttribute(const ArmAngles& arms);
// UserError naming `where` when `text` does not hold four angles.
ArmAngles ParseArmAnglesAttribute(const std::string& text, const std::string& where);

void WriteFrameExr(const std::string& path, const Frame& frame,
                   const std::map<std::string, std::string>& extra = {});
// UserError naming the file when it is not a frame file.
Frame ReadFrameExr(const std::string& path,
                   std::map<std::string, std::string>* attributes = nullptr);

}  // namespace acq
