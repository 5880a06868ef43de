// Moving the gantry between poses (issue 5, kinematics): how long a move takes, whether it is
// safe all the way, and the shortest safe order in which to visit a set of directions.
//
// Axes: light theta, light phi, camera theta, camera phi. Each moves with a trapezoidal speed
// profile (accelerate, cruise, decelerate); the four move together and a move lasts as long as
// its slowest axis, plus the settle time. A MOVE commands absolute angles (firmware_protocol/
// PROTOCOL.md) and each axis travels straight from its angle to the commanded one: an azimuth
// does not wrap (170 to -170 degrees is 340 degrees of travel, through 0), so the planner costs
// and collision-checks that path, not the shorter way round the firmware does not take.
// Isotropic BRDFs leave the azimuth of the half vector (phi_h) free: rotating both arms together
// about the normal gives the same measurement, so the planner chooses it per pose to shorten
// the moves.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brdf/directions.h"
#include "core/gantry_geometry.h"
#include "core/motion_profile.h"

namespace acq {

// Per-axis speed (rad/s) and acceleration (rad/s^2).
using AxisLimits = TrapezoidProfile;

// How the planner chooses each pose's half-vector azimuth (phi_h).
enum class HalfVectorAzimuths {
  kFastest,  // whatever makes the moves shortest (the half vectors may share one side)
  // Spread round the sample's normal (SpreadHalfVectorAzimuths), each pose within a tolerance
  // of its own (the narrowest of kSpreadTolerancesDeg that leaves a safe route): a facet tilted
  // any way then has some view's highlight near it, which a relief's normals need
  // (docs/reconstruction.md, "Half vectors all round").
  kSpread,
};
const char* ToString(HalfVectorAzimuths a);  // "fastest", "spread"
std::optional<HalfVectorAzimuths> HalfVectorAzimuthsNamed(const std::string& name);
// Tried in turn until a route is collision-free; past the last, any azimuth (the fastest).
inline constexpr double kSpreadTolerancesDeg[] = {10, 20, 45, 90};

struct GantryMotion {
  AxisLimits theta{DegToRad(30), DegToRad(60)}, phi{DegToRad(30), DegToRad(60)};  // both arms
  double settle_s = 0.5;
  DirectionConstraints constraints;  // reach and arm separation, checked at and between poses
  ArmAngles home{DegToRad(45), 0, 0, 0};
  int phi_h_steps = 72;  // azimuths tried per pose (every 5 degrees)
  HalfVectorAzimuths half_vector_azimuths = HalfVectorAzimuths::kFastest;

  void Check() const;  // throws UserError
  // Sets the axis speeds, accelerations and settle time from a source of named values in the
  // user's units (theta_speed_deg_s, theta_accel_deg_s2, phi_speed_deg_s, phi_accel_deg_s2,
  // settle_s): the plan's keys and, with '-' for '_', the CLI's flags. `get` returns the value
  // or the fallback it is given (the current one) when the name is absent.
  void ReadAxes(const std::function<double(const std::string& name, double fallback)>& get);
  double MoveSeconds(const ArmAngles& from, const ArmAngles& to) const;
  // The slower axis's profile: what a move's or homing's timeout is derived from.
  const AxisLimits& SlowestAxis() const { return theta.speed < phi.speed ? theta : phi; }
  // Empty when every point of the straight move (in axis space) keeps the constraints, else why.
  std::string MoveViolation(const ArmAngles& from, const ArmAngles& to) const;
};

struct PlannedPose {
  std::size_t index;  // into the directions given
  ArmAngles arms;
  double move_s;  // from the previous pose (or home)
};

struct VisitPlan {
  std::vector<PlannedPose> poses;
  double total_s = 0;  // all moves and settles, home to the last pose
  // kSpread: how far (degrees) a pose may lie from its spread azimuth in this plan; 0 when the
  // azimuths are the fastest (asked for, or no tolerance left a safe route).
  double spread_tolerance_deg = 0;
};

// Throws UserError naming the direction (its file:line) and the rule when a pose cannot be
// reached or no azimuth keeps the arms apart.
void CheckReachable(const std::vector<Direction>& directions, const GantryMotion& motion);

// Each direction's half-vector azimuth (radians, on the grid of `steps` per turn) so that the
// half vectors lie as far apart as they can: in order of theta_h (then as given), each takes
// the azimuth farthest from the half vectors placed before it (the first of equals). A
// direction whose half vector is the normal (theta_h under 0.5 degree) gets 0, its azimuth
// being no matter. Deterministic.
std::vector<double> SpreadHalfVectorAzimuths(const std::vector<Direction>& directions, int steps);

// The widest gap a relief's facet can fall in: over facets tilted up to `max_tilt` (radians)
// from the sample's normal, the largest angle from a facet's normal to the nearest of the
// plan's half vectors at the sample's centre (radians). A mirror-like ink's normal in a gap
// shows no highlight in any view, so the views cannot place it (docs/reconstruction.md).
double WidestHalfVectorGap(const VisitPlan& plan, double max_tilt);
// The tilts the planner's outputs report the gap over (degrees): the embossed card's edges are
// 10 degrees, a woven fabric's or a brush stroke's rarely steeper than 15.
inline constexpr double kReliefTiltDeg = 15;

// The directions in the given order, each at phi_h = 0 (what a naive run does).
VisitPlan PlanInFileOrder(const std::vector<Direction>& directions, const GantryMotion& motion);
// The given order, with the best phi_h for each pose (dynamic programming over the azimuths).
VisitPlan PlanBestAzimuths(const std::vector<Direction>& directions,
                           const std::vector<std::size_t>& order, const GantryMotion& motion);
// The shortest order found: nearest neighbour, then 2-opt, each order costed with the best
// azimuths. Deterministic.
VisitPlan PlanShortest(const std::vector<Direction>& directions, const GantryMotion& motion);

}  // namespace acq
