#include "hw/gantry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "core/stop_request.h"
#include "gantry_protocol.h"

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

namespace {

// "STALL (an axis did not follow its command), LIMIT (...)": the protocol's names and meanings
// of the bits set (gantry_vocabulary.def).
std::string DescribeFaults(std::uint16_t bits) {
  std::string out;
  for (int b = 0; b < 16; ++b) {
    const std::uint16_t bit = std::uint16_t(1u << b);
    if (!(bits & bit)) continue;
    out += (out.empty() ? "" : ", ") + std::string(gp_fault_name(bit)) + " (" +
           gp_fault_meaning(bit) + ")";
  }
  return out;
}

enum class Motion { kMove, kHoming };

// Waits until the arms stand still, renewing the lease; throws on a fault, on a stop signal
// (the arms stopped first) and when `timeout_s` passes on the controller's clock.
void WaitUntilStill(Gantry& gantry, double timeout_s, Motion motion) {
  const std::string what = motion == Motion::kMove ? "the move" : "homing";
  // Elapsed time on the controller's clock: the time the move itself takes (a simulated gantry
  // runs faster than the wall clock). The wall clock only guards against a frozen device clock.
  const std::uint32_t start_ms = gantry.Status().device_clock_ms;
  const auto wall_start = std::chrono::steady_clock::now();
  for (;;) {
    const GantryStatus s = gantry.Status();
    if (s.fault_bits)
      throw UserError("gantry", "fault during " + what + ": " + DescribeFaults(s.fault_bits),
                      "the arms are stopped; check for an obstruction or a tripped limit, then "
                      "clear the fault and resume");
    if (!s.Moving()) return;
    if (StopRequested()) {
      gantry.Stop();
      ThrowIfStopRequested();
    }
    const double elapsed_s = std::uint32_t(s.device_clock_ms - start_ms) / 1000.0;  // wraps
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (elapsed_s > timeout_s || wall_s > 10 * timeout_s) {
      char seconds[32];
      std::snprintf(seconds, sizeof seconds, "%.1f", timeout_s);
      gantry.Stop();
      throw UserError("gantry",
                      (motion == Motion::kMove ? "the arms did not arrive" : "homing did not end") +
                          std::string(" within ") + seconds + " s",
                      "the arms were stopped; check the axis speeds in the plan against the "
                      "gantry's and look for an obstruction");
    }
    gantry.RenewLease(2000);
  }
}

}  // namespace

void MoveAndWait(Gantry& gantry, const ArmAngles& target, double timeout_s) {
  gantry.RenewLease(2000);
  gantry.MoveTo(target);
  WaitUntilStill(gantry, timeout_s, Motion::kMove);
}

double HomingTimeoutSeconds(const TrapezoidProfile& axis, double settle_s) {
  // Homing may sweep an axis over its whole range (a half turn in theta, a whole one in phi).
  return 1.5 * (axis.Duration(2 * M_PI) + settle_s) + 2.0;
}

void HomeAndWait(Gantry& gantry, double timeout_s) {
  gantry.RenewLease(2000);
  gantry.Home();
  WaitUntilStill(gantry, timeout_s, Motion::kHoming);
  const GantryStatus s = gantry.Status();
  if (!s.Homed())
    throw UserError(
        "gantry",
        "homing ended with axes not homed (mask " + std::to_string(int(s.homed_mask)) + " of 15)",
        "check the home switches and run acqd again");
}

}  // namespace acq
