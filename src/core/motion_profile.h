// The trapezoidal motion profile of one gantry axis: accelerate at a, cruise at v, decelerate
// at a (a triangle when the distance is too short to reach v). Written once, used by the
// planner (how long a move takes) and by the simulated firmware (where an axis is).
#pragma once

#include <cmath>

namespace acq {

struct TrapezoidProfile {
  double speed;         // units/s, > 0
  double acceleration;  // units/s^2, > 0

  double Duration(double distance) const {
    const double d = std::abs(distance);
    if (d >= speed * speed / acceleration) return d / speed + speed / acceleration;
    return 2 * std::sqrt(d / acceleration);
  }
  // Signed distance covered t seconds into a move of `distance` (clamped to the move).
  double Position(double distance, double t) const {
    const double d = std::abs(distance), total = Duration(distance);
    if (t <= 0) return 0;
    if (t >= total) return distance;
    const double ramp = d >= speed * speed / acceleration ? speed / acceleration : total / 2;
    const double peak = acceleration * ramp;
    double s;
    if (t < ramp) {
      s = 0.5 * acceleration * t * t;
    } else if (t < total - ramp) {
      s = 0.5 * acceleration * ramp * ramp + peak * (t - ramp);
    } else {
      const double left = total - t;
      s = d - 0.5 * acceleration * left * left;
    }
    return std::copysign(s, distance);
  }
};

}  // namespace acq
