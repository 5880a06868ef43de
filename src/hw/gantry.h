// The gantry as the rest of the product sees it (docs/architecture.md: one interface per hardware
// kind). Implementations: ProtocolGantry (our wire protocol over any byte transport: USB bulk
// endpoints, a socket, an in-process simulator). Angles in radians, in the sample frame.
#pragma once

#include <cstdint>

#include "core/gantry_geometry.h"
#include "core/motion_profile.h"

namespace acq {

struct GantryStatus {
  ArmAngles commanded, measured;
  std::uint8_t moving_mask = 0, homed_mask = 0, limit_mask = 0;
  std::uint16_t fault_bits = 0;
  std::uint32_t device_clock_ms = 0, last_command_id = 0;
  bool Homed() const { return homed_mask == 0x0F; }
  bool Moving() const { return moving_mask != 0; }
};

class Gantry {
 public:
  virtual ~Gantry() = default;
  // Each throws UserError ("gantry: ...") with the firmware's reason when refused, and when the
  // device stops answering.
  virtual void Home() = 0;
  virtual void MoveTo(const ArmAngles& target) = 0;  // returns once accepted, not arrived
  virtual void Stop() = 0;
  virtual void EmergencyStop() = 0;  // accepted in every state
  virtual GantryStatus Status() = 0;
  virtual void SetLight(bool on, double level) = 0;  // level in [0, 1]
  virtual void RenewLease(int milliseconds) = 0;
  virtual void ClearFaults(std::uint16_t bits) = 0;
  // Requests the link sent again since the gantry was opened (0 where there is no link).
  virtual int retransmissions() const { return 0; }
};

// Moves and waits until the arms have arrived and settled, renewing the lease meanwhile; throws
// when the gantry reports a fault or does not arrive within `timeout_s`, and Stopped on a stop
// signal (core/stop_request.h), the arms stopped first.
void MoveAndWait(Gantry& gantry, const ArmAngles& target, double timeout_s);
// The same with the timeout derived from the move: the slowest axis (`axis`, the slower of the
// gantry's profiles) over the largest travel, plus the settle time, with 50 % and 2 s of margin
// for polling and link latency.
double MoveTimeoutSeconds(const ArmAngles& from, const ArmAngles& to, const TrapezoidProfile& axis,
                          double settle_s);
void MoveAndWait(Gantry& gantry, const ArmAngles& target, const TrapezoidProfile& axis,
                 double settle_s);
// Homes every axis and waits as a move does (faults, a stop signal, the timeout: a sweep of a
// whole turn on the slowest axis, with the same margins); throws when an axis is not homed
// after.
double HomingTimeoutSeconds(const TrapezoidProfile& axis, double settle_s);
void HomeAndWait(Gantry& gantry, double timeout_s);

}  // namespace acq
