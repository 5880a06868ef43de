#include "acq/move_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/angles.h"
#include "core/error.h"
#include "core/rusinkiewicz.h"

namespace acq {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double WrapDelta(double a) {
  return std::remainder(a, 2 * kPi);
}  // the shorter way round, for comparing azimuths (not for moves: see move_planner.h)

// The arms of a direction with the half vector's azimuth rotated by phi_h.
ArmAngles Rotated(const Direction& d, double phi_h) {
  RusinkiewiczAngles a = d.angles;
  a.phi_h = phi_h;
  return ArmAnglesFor(a);
}

std::string Deg(double rad) {
  return DegString(rad, 0);
}

// A half vector with its azimuth free: at the pole it is the normal whatever the azimuth.
bool AtPole(const Direction& d) {
  return d.angles.theta_h < DegToRad(0.5);
}

}  // namespace

const char* ToString(HalfVectorAzimuths a) {
  return a == HalfVectorAzimuths::kSpread ? "spread" : "fastest";
}

std::optional<HalfVectorAzimuths> HalfVectorAzimuthsNamed(const std::string& name) {
  for (HalfVectorAzimuths a : {HalfVectorAzimuths::kFastest, HalfVectorAzimuths::kSpread})
    if (name == ToString(a)) return a;
  return std::nullopt;
}

std::vector<double> SpreadHalfVectorAzimuths(const std::vector<Direction>& dirs, int steps) {
  std::vector<std::size_t> order(dirs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return dirs[a].angles.theta_h < dirs[b].angles.theta_h;
  });
  std::vector<double> azimuths(dirs.size(), 0.0);
  std::vector<Eigen::Vector3d> placed;
  for (std::size_t i : order) {
    const double theta_h = dirs[i].angles.theta_h;
    // The cosine of the angle to the nearest placed half vector: smaller is farther (and may be
    // negative, past 90 degrees).
    double best_phi = 0, best_nearest = kInf;
    for (int s = 0; s < steps && !AtPole(dirs[i]) && !placed.empty(); ++s) {
      const double phi = 2 * kPi * s / steps;
      const Eigen::Vector3d h = SphericalDirection(theta_h, phi);
      double nearest = -1;
      for (const Eigen::Vector3d& p : placed) nearest = std::max(nearest, h.dot(p));
      if (nearest < best_nearest - 1e-12) best_nearest = nearest, best_phi = phi;
    }
    azimuths[i] = best_phi;
    placed.push_back(SphericalDirection(theta_h, best_phi));
  }
  return azimuths;
}

void GantryMotion::Check() const {
  // Physical ranges (issue 22): an arm faster than 360 deg/s or 3600 deg/s^2 is no gantry's,
  // a settle over a minute a typing error; both also keep the planner's times finite.
  for (const AxisLimits* l : {&theta, &phi})
    if (!(l->speed > 0 && l->speed <= DegToRad(360)) ||
        !(l->acceleration > 0 && l->acceleration <= DegToRad(3600)))
      throw UserError("gantry motion",
                      "axis speeds must be in (0, 360] deg/s and accelerations in (0, 3600] "
                      "deg/s^2");
  if (!(settle_s >= 0 && settle_s <= 60)) throw UserError("--settle-s", "must be from 0 to 60 s");
  if (phi_h_steps < 1) throw UserError("phi_h steps", "must be at least 1");
  constraints.Check();
}

void GantryMotion::ReadAxes(
    const std::function<double(const std::string& name, double fallback)>& get) {
  theta.speed = DegToRad(get("theta_speed_deg_s", RadToDeg(theta.speed)));
  theta.acceleration = DegToRad(get("theta_accel_deg_s2", RadToDeg(theta.acceleration)));
  phi.speed = DegToRad(get("phi_speed_deg_s", RadToDeg(phi.speed)));
  phi.acceleration = DegToRad(get("phi_accel_deg_s2", RadToDeg(phi.acceleration)));
  settle_s = get("settle_s", settle_s);
}

double GantryMotion::MoveSeconds(const ArmAngles& a, const ArmAngles& b) const {
  return std::max({theta.Duration(b.light_theta - a.light_theta),
                   phi.Duration(b.light_phi - a.light_phi),
                   theta.Duration(b.camera_theta - a.camera_theta),
                   phi.Duration(b.camera_phi - a.camera_phi)}) +
         settle_s;
}

std::string GantryMotion::MoveViolation(const ArmAngles& a, const ArmAngles& b) const {
  // All axes move together from start to end: sample the path finely (1 degree of the longest
  // axis travel) and check the arms at every sample. The planner asks this for every pair of
  // (pose, azimuth) states, so the samples are checked on the angles directly (horizon, light
  // reach, and the separation by the spherical law of cosines against cos(min_separation)); the
  // constraints' own Violation() words the first sample that fails.
  const double d_light_theta = b.light_theta - a.light_theta;
  const double d_light_phi = b.light_phi - a.light_phi;
  const double d_camera_theta = b.camera_theta - a.camera_theta;
  const double d_camera_phi = b.camera_phi - a.camera_phi;
  const double travel = std::max({std::abs(d_light_theta), std::abs(d_light_phi),
                                  std::abs(d_camera_theta), std::abs(d_camera_phi)});
  const int steps = std::max(1, int(std::ceil(travel / DegToRad(1))));
  const DirectionConstraints& c = constraints;
  const double cos_min_separation = std::cos(c.min_separation);
  // Each angle the checks need moves by a constant step from sample to sample, so its cosine
  // and sine follow by rotation (angle addition) instead of a trigonometric call each: the
  // calls were nearly all of the planner's time (4 s for a 20-direction session). Over at most
  // 360 steps the recurrence drifts by ~1e-13, far below any limit's meaning.
  struct Rotation {
    double cos, sin, step_cos, step_sin;
    Rotation(double angle, double step)
        : cos(std::cos(angle)),
          sin(std::sin(angle)),
          step_cos(std::cos(step)),
          step_sin(std::sin(step)) {}
    void Advance() {
      const double c = cos * step_cos - sin * step_sin;
      sin = sin * step_cos + cos * step_sin;
      cos = c;
    }
  };
  Rotation light(a.light_theta, d_light_theta / steps),
      camera(a.camera_theta, d_camera_theta / steps),
      azimuth(a.light_phi - a.camera_phi, (d_light_phi - d_camera_phi) / steps);
  for (int i = 0; i <= steps; ++i, light.Advance(), camera.Advance(), azimuth.Advance()) {
    const double t = double(i) / steps;
    const ArmAngles p{a.light_theta + t * d_light_theta, a.light_phi + t * d_light_phi,
                      a.camera_theta + t * d_camera_theta, a.camera_phi + t * d_camera_phi};
    bool ok = light.cos > 0 && camera.cos > 0;
    if (ok && c.enabled) {
      const double cos_separation = light.cos * camera.cos + light.sin * camera.sin * azimuth.cos;
      ok = p.light_theta <= c.max_light_zenith && cos_separation <= cos_min_separation;
    }
    if (ok) continue;
    const std::string why = c.Violation(p);
    // The camera-zenith rule is about where images are taken, not about moving through.
    if (!why.empty() && why.find("camera zenith") == std::string::npos) return why;
  }
  return {};
}

void CheckReachable(const std::vector<Direction>& directions, const GantryMotion& motion) {
  motion.Check();
  for (const Direction& d : directions) {
    // phi_h does not change zeniths or the separation: one azimuth decides.
    const std::string why = motion.constraints.Violation(Rotated(d, 0));
    if (!why.empty())
      throw UserError(d.where,
                      "direction (theta_h " + Deg(d.angles.theta_h) + ", theta_d " +
                          Deg(d.angles.theta_d) + ", phi_d " + Deg(d.angles.phi_d) +
                          " deg) cannot be taken: " + why,
                      "drop it, or re-plan the directions with `acq directions optimize` and the "
                      "gantry's limits");
  }
}

namespace {

// Move times between (pose, azimuth) states, unsafe moves infinite; each computed at most once,
// since the search costs many orders over the same moves.
class RouteCosts {
 public:
  // spread_tolerance > 0: each pose within it of its spread azimuth (radians); else any azimuth.
  RouteCosts(const std::vector<Direction>& dirs, const GantryMotion& m, double spread_tolerance)
      : m_(m), steps_(m.phi_h_steps), states_(dirs.size() * std::size_t(steps_)) {
    arms_.reserve(states_);
    for (const Direction& d : dirs)
      for (int s = 0; s < steps_; ++s) arms_.push_back(Rotated(d, 2 * kPi * s / steps_));
    cache_.assign(states_ * states_, -1.0f);
    home_.assign(states_, -1.0f);
    allowed_.assign(states_, true);
    if (spread_tolerance > 0) Spread(dirs, spread_tolerance);
  }
  int Steps() const { return steps_; }
  const ArmAngles& Arms(std::size_t pose, int s) const { return arms_[State(pose, s)]; }
  double FromHome(std::size_t pose, int s) {
    if (!allowed_[State(pose, s)]) return kInf;
    return Cost(m_.home, Arms(pose, s), &home_[State(pose, s)]);
  }
  double Move(std::size_t a, int s, std::size_t b, int t) {
    if (!allowed_[State(a, s)] || !allowed_[State(b, t)]) return kInf;
    return Cost(Arms(a, s), Arms(b, t), &cache_[State(a, s) * states_ + State(b, t)]);
  }

 private:
  // Each pose only within the tolerance of its spread azimuth (any azimuth at the pole).
  void Spread(const std::vector<Direction>& dirs, double tolerance) {
    const std::vector<double> target = SpreadHalfVectorAzimuths(dirs, steps_);
    for (std::size_t pose = 0; pose < dirs.size(); ++pose)
      for (int s = 0; s < steps_ && !AtPole(dirs[pose]); ++s)
        allowed_[State(pose, s)] =
            std::abs(WrapDelta(2 * kPi * s / steps_ - target[pose])) <= tolerance + 1e-9;
  }
  std::size_t State(std::size_t pose, int s) const {
    return pose * std::size_t(steps_) + std::size_t(s);
  }
  double Cost(const ArmAngles& a, const ArmAngles& b, float* slot) {
    if (*slot < 0)
      *slot = m_.MoveViolation(a, b).empty() ? float(m_.MoveSeconds(a, b))
                                             : std::numeric_limits<float>::infinity();
    return *slot;
  }
  const GantryMotion& m_;
  int steps_;
  std::size_t states_;
  std::vector<ArmAngles> arms_;
  std::vector<float> cache_, home_;
  std::vector<bool> allowed_;
};

// Dynamic programming over the azimuths along a route: cost[i][s] is the least time to reach
// the i-th pose at azimuth step s. Returns a plan with total_s = inf when no safe one exists.
VisitPlan BestAzimuths(RouteCosts& costs, const std::vector<std::size_t>& order) {
  const int steps = costs.Steps();
  const std::size_t n = order.size();
  VisitPlan plan;
  if (n == 0) return plan;
  std::vector<std::vector<double>> cost(n, std::vector<double>(steps, kInf));
  std::vector<std::vector<int>> from(n, std::vector<int>(steps, -1));
  for (int s = 0; s < steps; ++s) cost[0][s] = costs.FromHome(order[0], s);
  for (std::size_t i = 1; i < n; ++i)
    for (int s = 0; s < steps; ++s)
      for (int r = 0; r < steps; ++r) {
        if (cost[i - 1][r] == kInf) continue;
        const double c = cost[i - 1][r] + costs.Move(order[i - 1], r, order[i], s);
        if (c < cost[i][s]) cost[i][s] = c, from[i][s] = r;
      }
  int s = int(std::min_element(cost[n - 1].begin(), cost[n - 1].end()) - cost[n - 1].begin());
  plan.total_s = cost[n - 1][s];
  if (plan.total_s == kInf) return plan;
  plan.poses.resize(n);
  for (std::size_t i = n; i-- > 0;) {
    const int prev = from[i][s];
    const double move =
        i == 0 ? costs.FromHome(order[0], s) : costs.Move(order[i - 1], prev, order[i], s);
    plan.poses[i] = {order[i], costs.Arms(order[i], s), move};
    s = prev;
  }
  return plan;
}

VisitPlan RequireSafe(VisitPlan plan) {
  if (plan.total_s == kInf)
    throw UserError("move order", "no collision-free azimuths exist for this order",
                    "check the arms' separation limit against the directions");
  return plan;
}

// The first spread tolerance of kSpreadTolerancesDeg whose poses leave a collision-free route
// for `plan_with` (a plan with total_s = inf where none is safe); 0 when the half vectors are
// not spread or none did (then any azimuth).
template <class PlanWith>
VisitPlan SpreadAsFarAsSafe(const GantryMotion& m, const PlanWith& plan_with) {
  if (m.half_vector_azimuths == HalfVectorAzimuths::kSpread)
    for (double tolerance_deg : kSpreadTolerancesDeg) {
      VisitPlan plan = plan_with(DegToRad(tolerance_deg));
      if (plan.total_s == kInf) continue;
      plan.spread_tolerance_deg = tolerance_deg;
      return plan;
    }
  return RequireSafe(plan_with(0.0));
}

}  // namespace

VisitPlan PlanBestAzimuths(const std::vector<Direction>& dirs,
                           const std::vector<std::size_t>& order, const GantryMotion& m) {
  CheckReachable(dirs, m);
  return SpreadAsFarAsSafe(m, [&](double tolerance) {
    RouteCosts costs(dirs, m, tolerance);
    return BestAzimuths(costs, order);
  });
}

double WidestHalfVectorGap(const VisitPlan& plan, double max_tilt) {
  std::vector<Eigen::Vector3d> halves;
  for (const PlannedPose& p : plan.poses) {
    const DirectionPair d = DirectionsOf(p.arms);
    halves.push_back((d.in + d.out).normalized());
  }
  if (halves.empty()) return kPi;
  // Facets on rings a quarter of a degree apart, a quarter of a degree round each.
  const double step = DegToRad(0.25);
  double widest = 0;
  for (double tilt = 0; tilt <= max_tilt + 1e-12; tilt += step) {
    const int around = std::max(1, int(std::ceil(2 * kPi * std::sin(tilt) / step)));
    for (int k = 0; k < around; ++k) {
      const Eigen::Vector3d facet = SphericalDirection(tilt, 2 * kPi * k / around);
      double nearest = -1;
      for (const Eigen::Vector3d& h : halves) nearest = std::max(nearest, facet.dot(h));
      widest = std::max(widest, std::acos(std::clamp(nearest, -1.0, 1.0)));
    }
  }
  return widest;
}

VisitPlan PlanInFileOrder(const std::vector<Direction>& dirs, const GantryMotion& m) {
  VisitPlan plan;
  ArmAngles at = m.home;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const ArmAngles next = Rotated(dirs[i], 0);
    plan.poses.push_back({i, next, m.MoveSeconds(at, next)});
    plan.total_s += plan.poses.back().move_s;
    at = next;
  }
  return plan;
}

namespace {

// PlanShortest with the poses' azimuths as RouteCosts allows them (total_s = inf when unsafe).
VisitPlan ShortestWith(const std::vector<Direction>& dirs, const GantryMotion& m,
                       double spread_tolerance) {
  const std::size_t n = dirs.size();
  RouteCosts costs(dirs, m, spread_tolerance);
  // Nearest neighbour over (pose, azimuth) states, then 2-opt with every candidate order costed
  // exactly with its best azimuths.
  std::vector<std::size_t> order;
  std::vector<bool> used(n, false);
  std::size_t at_pose = 0;
  int at_s = -1;  // home
  for (std::size_t k = 0; k < n; ++k) {
    std::size_t best = n;
    int best_s = 0;
    double best_cost = kInf;
    for (std::size_t j = 0; j < n; ++j) {
      if (used[j]) continue;
      for (int s = 0; s < costs.Steps(); ++s) {
        const double c = at_s < 0 ? costs.FromHome(j, s) : costs.Move(at_pose, at_s, j, s);
        if (c < best_cost) best_cost = c, best = j, best_s = s;
      }
    }
    if (best == n) {  // nothing reachable safely from here: take the first left, DP decides
      best = std::size_t(std::find(used.begin(), used.end(), false) - used.begin());
    }
    used[best] = true;
    order.push_back(best);
    at_pose = best;
    at_s = best_s;
  }
  VisitPlan plan = BestAzimuths(costs, order);
  for (bool improved = true; improved;) {
    improved = false;
    for (std::size_t i = 0; i + 1 < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        std::vector<std::size_t> trial = order;
        std::reverse(trial.begin() + long(i), trial.begin() + long(j) + 1);
        const VisitPlan p = BestAzimuths(costs, trial);
        if (p.total_s < plan.total_s - 1e-9) {
          plan = p;
          order = trial;
          improved = true;
        }
      }
  }
  return plan;
}

}  // namespace

VisitPlan PlanShortest(const std::vector<Direction>& dirs, const GantryMotion& m) {
  CheckReachable(dirs, m);
  return SpreadAsFarAsSafe(m, [&](double tolerance) { return ShortestWith(dirs, m, tolerance); });
}

}  // namespace acq
