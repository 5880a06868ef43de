// Command-line flags shared by the direction commands: the planning constraints and the
// near-field geometry, in degrees and millimetres at the edge, radians inside.
#pragma once

#include <vector>

#include "cli/args.h"
#include "core/gantry_geometry.h"

namespace acq::cli {

inline const std::set<std::string> kConstraintOptions = {
    "max-camera-zenith-deg", "max-light-zenith-deg", "min-separation-deg"};
inline const std::set<std::string> kGeometryOptions = {"fov-deg", "sample-size-mm",
                                                       "camera-distance-mm", "light-distance-mm"};

// A light and camera arm pose: --light-theta-deg 30 --light-phi-deg 0 --camera-theta-deg 0
// --camera-phi-deg 0 by default (the reference view, the light 30 degrees off).
inline const std::set<std::string> kArmOptions = {"light-theta-deg", "light-phi-deg",
                                                  "camera-theta-deg", "camera-phi-deg"};
ArmAngles ArmsFrom(const Args& args);

DirectionConstraints ConstraintsFrom(const Args& args);  // --unconstrained: horizon only

// One geometry per --fov-deg value (a comma list; default 0), or one from --sample-size-mm.
std::vector<NearFieldGeometry> GeometriesFrom(const Args& args);
// The field of view, in degrees, that a geometry's sample fills.
double FovDeg(const NearFieldGeometry& g);

}  // namespace acq::cli
