#include "sim/gantry_firmware.h"

#include <algorithm>
#include <cmath>

namespace acq::sim {
namespace {}  // namespace

SimGantryFirmware::SimGantryFirmware(FirmwareOptions options) : options_(options), rng_(1) {
  Reset();
}

void SimGantryFirmware::Reset() {
  gp_decoder_init(&decoder_);
  rng_.seed(faults.seed);
  boot_s_ = now_s_;  // the device clock restarts
  homed_ = false;
  faults_ = 0;
  last_command_id_ = 0;
  lease_until_s_ = 0;
  // Parked where the arms rest after power-up: light at 45 degrees, camera overhead.
  const double parked[4] = {DegToRad(45), 0, 0, 0};
  for (int i = 0; i < GP_AXIS_COUNT; ++i) axes_[i] = {parked[i], parked[i], now_s_, parked[i]};
}

ArmAngles SimGantryFirmware::Measured() const {
  return {axes_[0].position, axes_[1].position, axes_[2].position, axes_[3].position};
}

bool SimGantryFirmware::Moving() const {
  // An axis with a move to make is moving until it has arrived and settled; one at rest
  // (from == to) is not, whatever its start time.
  for (const Axis& a : axes_)
    if (a.from != a.to &&
        now_s_ < a.start_s + options_.axis.Duration(a.to - a.from) + options_.settle_s)
      return true;
  return false;
}

void SimGantryFirmware::StopAxes() {
  for (Axis& a : axes_) a = {a.position, a.position, now_s_, a.position};
}

void SimGantryFirmware::Advance(double seconds) {
  const double end = now_s_ + seconds;
  // Small steps so the lease and the stall are noticed mid-move.
  while (now_s_ < end) {
    now_s_ = std::min(end, now_s_ + 0.01);
    for (int i = 0; i < GP_AXIS_COUNT; ++i) {
      Axis& a = axes_[i];
      if (i == faults.stalled_axis) {
        if (a.to != a.from) {
          faults_ |= GP_FAULT_BIT_STALL;
          StopAxes();
        }
        continue;
      }
      a.position = a.from + options_.axis.Position(a.to - a.from, now_s_ - a.start_s);
    }
    if (!Moving())
      for (Axis& a : axes_) a.from = a.to = a.position;  // arrived and settled: at rest
    if (Moving() && now_s_ > lease_until_s_) {
      faults_ |= GP_FAULT_BIT_LEASE_EXPIRED;
      StopAxes();
    }
    if (faults.trip_limit && Moving()) {
      faults_ |= GP_FAULT_BIT_LIMIT;
      StopAxes();
    }
  }
}

gp_message SimGantryFirmware::Result(const gp_message& request, std::uint8_t code) const {
  gp_message r{};
  r.sequence = request.sequence;
  r.id = GP_RESULT;
  r.body.RESULT = {request.sequence, request.id, code};
  return r;
}

gp_message SimGantryFirmware::StatusMessage(std::uint8_t sequence) const {
  gp_message s{};
  s.sequence = sequence;
  s.id = GP_STATUS;
  gp_STATUS& b = s.body.STATUS;
  b.device_clock_ms = std::uint32_t((now_s_ - boot_s_) * 1000);
  b.light_theta_cmd_mdeg = gp_mdeg_from_rad(axes_[0].to);
  b.light_phi_cmd_mdeg = gp_mdeg_from_rad(axes_[1].to);
  b.camera_theta_cmd_mdeg = gp_mdeg_from_rad(axes_[2].to);
  b.camera_phi_cmd_mdeg = gp_mdeg_from_rad(axes_[3].to);
  b.light_theta_mdeg = gp_mdeg_from_rad(axes_[0].position);
  b.light_phi_mdeg = gp_mdeg_from_rad(axes_[1].position);
  b.camera_theta_mdeg = gp_mdeg_from_rad(axes_[2].position);
  b.camera_phi_mdeg = gp_mdeg_from_rad(axes_[3].position);
  b.moving_mask = Moving() ? 0x0F : 0;
  b.homed_mask = homed_ ? 0x0F : 0;
  b.limit_mask = (faults_ & GP_FAULT_BIT_LIMIT) ? 0x01 : 0;
  b.fault_bits = faults_;
  b.last_command_id = last_command_id_;
  return s;
}

gp_message SimGantryFirmware::Handle(const gp_message& m) {
  switch (m.id) {
    case GP_HELLO: {
      gp_message r{};
      r.sequence = m.sequence;
      r.id = GP_HELLO_REPLY;
      r.body.HELLO_REPLY = {options_.protocol_version, options_.schema_hash, options_.build};
      return r;
    }
    case GP_GET_STATUS:
      return StatusMessage(m.sequence);
    case GP_ESTOP:  // accepted in every state
      StopAxes();
      faults_ |= GP_FAULT_BIT_ESTOP;
      light_on_ = false;
      return Result(m, GP_OK);
    case GP_STOP:
      StopAxes();
      return Result(m, GP_OK);
    case GP_CLEAR_FAULT:
      faults_ &= std::uint16_t(~m.body.CLEAR_FAULT.fault_bits);
      if (m.body.CLEAR_FAULT.fault_bits & GP_FAULT_BIT_LIMIT) faults.trip_limit = false;
      return Result(m, GP_OK);
    case GP_LEASE:
      lease_until_s_ = now_s_ + m.body.LEASE.duration_ms / 1000.0 * options_.lease_time_scale;
      return Result(m, GP_OK);
    case GP_LIGHT:
      if (m.body.LIGHT.level_permille > 1000) return Result(m, GP_BAD_REQUEST);
      light_on_ = m.body.LIGHT.on != 0;
      return Result(m, GP_OK);
    case GP_HOME: {
      if (faults_) return Result(m, GP_FAULT);
      if (Moving()) return Result(m, GP_BUSY);
      const double home[4] = {DegToRad(45), 0, 0, 0};
      for (int i = 0; i < GP_AXIS_COUNT; ++i)
        axes_[i] = {axes_[i].position, home[i], now_s_, axes_[i].position};
      homed_ = true;
      lease_until_s_ = std::max(lease_until_s_, now_s_ + 60.0);  // homing carries its own lease
      return Result(m, GP_OK);
    }
    case GP_MOVE: {
      const gp_MOVE& mv = m.body.MOVE;
      if (mv.command_id != 0 && mv.command_id == last_command_id_) return Result(m, GP_DUPLICATE);
      if (faults_) return Result(m, GP_FAULT);
      if (!homed_) return Result(m, GP_NOT_HOMED);
      if (Moving()) return Result(m, GP_BUSY);
      if (now_s_ > lease_until_s_) return Result(m, GP_LEASE_EXPIRED);
      const ArmAngles target{
          gp_rad_from_mdeg(mv.light_theta_mdeg), gp_rad_from_mdeg(mv.light_phi_mdeg),
          gp_rad_from_mdeg(mv.camera_theta_mdeg), gp_rad_from_mdeg(mv.camera_phi_mdeg)};
      const std::string why = options_.limits.Violation(target);
      if (!why.empty())
        return Result(m, why.find("apart") != std::string::npos ? GP_COLLISION : GP_OUT_OF_RANGE);
      const double to[4] = {target.light_theta, target.light_phi, target.camera_theta,
                            target.camera_phi};
      for (int i = 0; i < GP_AXIS_COUNT; ++i)
        axes_[i] = {axes_[i].position, to[i], now_s_, axes_[i].position};
      last_command_id_ = mv.command_id;
      ++executed_moves_;
      return Result(m, GP_OK);
    }
    default:
      return Result(m, GP_BAD_REQUEST);
  }
}

void SimGantryFirmware::Emit(const gp_message& m, std::vector<std::uint8_t>* out) {
  std::uniform_real_distribution<double> u(0, 1);
  if (u(rng_) < faults.drop_reply_probability) return;
  std::uint8_t frame[GP_MAX_FRAME];
  const std::size_t n = gp_encode(&m, frame, sizeof frame);
  if (u(rng_) < faults.corrupt_reply_probability) frame[n / 2] ^= 0x5A;
  out->insert(out->end(), frame, frame + n);
}

void SimGantryFirmware::Receive(const std::uint8_t* data, std::size_t n,
                                std::vector<std::uint8_t>* out) {
  gp_message m;
  for (std::size_t i = 0; i < n; ++i) {
    int got = gp_decoder_push(&decoder_, data[i], &m);
    while (got) {
      Emit(Handle(m), out);
      got = gp_decoder_next(&decoder_, &m);
    }
  }
}

}  // namespace acq::sim
