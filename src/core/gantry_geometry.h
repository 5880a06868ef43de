// Where the gantry's arms must be for a light/view direction pair, which pairs the gantry may
// take (the planning constraints), and what each point of a finite sample really sees (the
// near-field effect). Angles in radians; lengths in millimetres.
//
// Frames: the sample frame has its origin at the sample centre, z along the normal and x along
// gantry azimuth 0 (docs/architecture.md). An arm at (theta, phi) points along
// (sin theta cos phi, sin theta sin phi, cos theta) from the sample centre.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/angles.h"
#include "core/rusinkiewicz.h"

namespace acq {

struct ArmAngles {
  double light_theta = 0, light_phi = 0;
  double camera_theta = 0, camera_phi = 0;
};

// Arm angles for a Rusinkiewicz direction (phi_h as given). By reciprocity either direction
// may be the camera's; the camera takes the one with the smaller zenith angle.
ArmAngles ArmAnglesFor(const RusinkiewiczAngles& a);
DirectionPair DirectionsOf(const ArmAngles& arms);  // in = light, out = camera

// The planning constraints on a direction pair. Defaults: the SVBRDF variant of the seed paper
// (camera below 65 degrees zenith), light within a typical arm's reach, and 20 degrees between
// light and camera so the arms clear each other (every seed direction has at least 30).
struct DirectionConstraints {
  double max_camera_zenith = DegToRad(65);
  double max_light_zenith = DegToRad(85);
  double min_separation = DegToRad(20);  // angle between light and camera
  bool enabled = true;  // false: only "both above the horizon" (the NJR15 situation)

  void Check() const;  // throws UserError on values out of range
  // Empty when allowed, else which rule fails and by how much, in degrees.
  std::string Violation(const ArmAngles& arms) const;
};

// The near field: a camera and a light at finite distances from the sample centre, and a
// square sample of a given side. Each position on the sample sees its own directions.
struct NearFieldGeometry {
  double camera_distance_mm = 1000;
  double light_distance_mm = 1000;
  double sample_size_mm = 0;  // 0: every position is the centre (far field)

  // The sample side that fills `fov` (full angle) of a camera at camera_distance_mm.
  static double SampleSizeForFov(double fov, double camera_distance_mm);
  // grid x grid positions spread uniformly over the sample: the centres of equal cells (the
  // paper's uniformly sampled positions), or with `to_edges` from corner to corner, so the
  // extremes of the field of view are among them (what a constraint check needs).
  std::vector<Eigen::Vector2d> Positions(int grid, bool to_edges = false) const;
  // Light and camera directions seen from p_in_sample (z = 0), for arms whose directions from
  // the sample centre are `far` (DirectionsOf(arms); callers compute it once per pose).
  DirectionPair DirectionsAt(const DirectionPair& far, const Eigen::Vector2d& p_in_sample) const;
};

}  // namespace acq
