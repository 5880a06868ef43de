// The simulated gantry firmware: the microcontroller's behaviour, speaking the real protocol
// through the shared codec (firmware_protocol/). Homing, trapezoidal motion of the four axes,
// settle time, the collision interlock, the motion lease, latched faults, idempotent moves, and
// knobs to inject faults. Time is simulated (Advance), so tests run as fast as they compute.
// Its arm positions are what the simulated camera renders from.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "core/gantry_geometry.h"
#include "core/motion_profile.h"
#include "gantry_protocol.h"

namespace acq::sim {

struct FirmwareOptions {
  TrapezoidProfile axis{DegToRad(30), DegToRad(60)};  // rad/s, rad/s^2
  double settle_s = 0.5;
  DirectionConstraints limits;  // reach and the arms' separation (the collision interlock)
  std::uint32_t build = 1;
  std::uint32_t schema_hash = gp_schema_hash();  // change it to simulate other firmware
  std::uint16_t protocol_version = GP_PROTOCOL_VERSION;
  // The lease guards against a silent host, whose silence is wall-clock time: a firmware whose
  // clock runs this many times faster than the wall (the emulated USB gantry's time_scale)
  // counts its leases that much longer. Else a host stalled 0.1 s by a loaded machine loses a
  // 2 s lease at time_scale 20 (seen in CI: "MOVE refused: the motion lease has expired").
  double lease_time_scale = 1;
};

struct FirmwareFaults {
  double drop_reply_probability = 0;  // replies lost on the way back
  double corrupt_reply_probability = 0;
  int stalled_axis = -1;  // a gp_axis (GP_AXIS_LIGHT_THETA...): that axis stops following
  bool trip_limit = false;
  std::uint64_t seed = 1;
};

class SimGantryFirmware {
 public:
  explicit SimGantryFirmware(FirmwareOptions options = {});

  // Bytes from the host; reply bytes are appended to *out.
  void Receive(const std::uint8_t* data, std::size_t n, std::vector<std::uint8_t>* out);
  void Advance(double seconds);
  void Reset();  // a firmware reset: state lost, not homed

  ArmAngles Measured() const;
  double Now() const { return now_s_; }
  FirmwareFaults faults;
  int executed_moves() const { return executed_moves_; }

 private:
  struct Axis {
    double from = 0, to = 0, start_s = 0, position = 0;
  };
  gp_message Handle(const gp_message& m);
  gp_message Result(const gp_message& request, std::uint8_t code) const;
  gp_message StatusMessage(std::uint8_t sequence) const;
  bool Moving() const;
  void StopAxes();
  void Emit(const gp_message& m, std::vector<std::uint8_t>* out);

  FirmwareOptions options_;
  gp_decoder decoder_;
  std::mt19937_64 rng_;
  double now_s_ = 0, boot_s_ = 0;
  Axis axes_[4];
  bool homed_ = false;
  std::uint16_t faults_ = 0;
  std::uint32_t last_command_id_ = 0;
  double lease_until_s_ = 0;
  bool light_on_ = false;
  int executed_moves_ = 0;
};

}  // namespace acq::sim
