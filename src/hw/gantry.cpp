#include "hw/gantry.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.h"

namespace acq {

double MoveTimeoutSeconds(const ArmAngles& from, const ArmAngles& to, const TrapezoidProfile& axis,
                          double settle_s) {
  const double travel = std::max(
      {std::abs(to.light_theta - from.light_theta), std::abs(to.light_phi - from.light_phi),
       std::abs(to.camera_theta - from.camera_theta), std::abs(to.camera_phi - from.camera_phi)});
  return 1.5 * (axis.Duration(travel) + settle_s) + 2.0;
}

void MoveAndWait(Gantry& gantry, const ArmAngles& target, const TrapezoidProfile& axis,
                 double settle_s) {
  const ArmAngles from = gantry.Status().measured;
  MoveAndWait(gantry, target, MoveTimeoutSeconds(from, target, axis, settle_s));
}

void MoveAndWait(Gantry& gantry, const ArmAngles& target, double timeout_s) {
  gantry.RenewLease(2000);
  gantry.MoveTo(target);
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const GantryStatus s = gantry.Status();
    if (s.fault_bits)
      throw UserError("gantry", "fault during the move (bits " + std::to_string(s.fault_bits) + ")",
                      "the arms are stopped; check for an obstruction or a tripped limit, then "
                      "clear the fault and resume");
    if (!s.Moving()) return;
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout_s)
      throw UserError("gantry",
                      "the arms did not arrive within " + std::to_string(timeout_s) + " s",
                      "check the gantry; the lease stops the arms when not renewed");
    gantry.RenewLease(2000);
  }
}

}  // namespace acq
