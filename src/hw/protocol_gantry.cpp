#include "hw/protocol_gantry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/angles.h"
#include "core/error.h"

namespace acq {
namespace {

const char* ResultText(std::uint8_t code) {
  switch (code) {
    case GP_BUSY:
      return "busy (the arms are still moving)";
    case GP_NOT_HOMED:
      return "not homed";
    case GP_OUT_OF_RANGE:
      return "target out of the arms' reach";
    case GP_COLLISION:
      return "target would bring the arms too close (collision interlock)";
    case GP_FAULT:
      return "a fault is latched";
    case GP_LEASE_EXPIRED:
      return "the motion lease has expired";
    case GP_BAD_REQUEST:
      return "bad request";
    default:
      return "unknown result code";
  }
}

std::string Hex(std::uint32_t v) {
  char s[16];
  std::snprintf(s, sizeof s, "0x%08x", v);
  return s;
}

}  // namespace

ProtocolGantry::ProtocolGantry(ByteTransport& transport, ProtocolGantryOptions options)
    : transport_(transport), options_(options) {
  Handshake();
}

void ProtocolGantry::Handshake() {
  gp_decoder_init(&decoder_);
  gp_message hello{};
  hello.id = GP_HELLO;
  hello.body.HELLO = {GP_PROTOCOL_VERSION, gp_schema_hash()};
  hello.sequence = sequence_++;
  const gp_message reply = Exchange(hello, GP_HELLO_REPLY);
  const gp_HELLO_REPLY& r = reply.body.HELLO_REPLY;
  if (r.protocol_version != GP_PROTOCOL_VERSION || r.schema_hash != gp_schema_hash())
    throw UserError("gantry",
                    "firmware speaks protocol " + std::to_string(r.protocol_version) + " schema " +
                        Hex(r.schema_hash) + ", this host " + std::to_string(GP_PROTOCOL_VERSION) +
                        " schema " + Hex(gp_schema_hash()),
                    "flash the firmware built from this tree's firmware_protocol/");
  firmware_build_ = r.firmware_build;
}

gp_message ProtocolGantry::Request(gp_message request, std::uint8_t reply_id) {
  request.sequence = sequence_++;
  try {
    return Exchange(request, reply_id);
  } catch (const TransportGone& gone) {
    Reconnect(gone);
  }
  // The same frame again: the same sequence number and, for a MOVE, the same command id, which
  // the firmware acknowledges without moving twice if the first copy got through.
  return Exchange(request, reply_id);
}

void ProtocolGantry::Reconnect(const TransportGone& why) {
  if (!transport_.Reconnect(options_.reconnect_timeout_ms))
    throw TransportGone(why.where(),
                        why.problem() + "; it did not come back within " +
                            std::to_string(options_.reconnect_timeout_ms / 1000.0).substr(0, 4) +
                            " s",
                        why.fix());
  ++reconnects_;
  Handshake();
  ReadStatus();  // throws when the controller was reset meanwhile
}

gp_message ProtocolGantry::Exchange(const gp_message& request, std::uint8_t reply_id) {
  std::uint8_t frame[GP_MAX_FRAME];
  const std::size_t n = gp_encode(&request, frame, sizeof frame);
  for (int attempt = 0; attempt < options_.attempts; ++attempt) {
    if (attempt > 0) ++retransmissions_;
    transport_.Send(frame, n);
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(options_.reply_timeout_ms);
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                            deadline - std::chrono::steady_clock::now())
                            .count();
      if (left <= 0) break;
      std::uint8_t buf[256];
      const std::size_t got = transport_.Receive(buf, sizeof buf, int(left));
      if (got == 0) break;  // the transport says nothing came in time
      gp_message m;
      for (std::size_t i = 0; i < got; ++i) {
        int have = gp_decoder_push(&decoder_, buf[i], &m);
        while (have) {
          // Replies to older, retransmitted requests are stale: ignore them.
          if (m.sequence == request.sequence && m.id == reply_id) return m;
          have = gp_decoder_next(&decoder_, &m);
        }
      }
    }
  }
  throw UserError("gantry",
                  std::string("no answer to ") + gp_message_name(request.id) + " after " +
                      std::to_string(options_.attempts) + " attempts",
                  "check the USB cable and the gantry's power; the arms stop by themselves when "
                  "the motion lease runs out");
}

void ProtocolGantry::Command(gp_message request) {
  const gp_message reply = Request(request, GP_RESULT);
  const std::uint8_t code = reply.body.RESULT.code;
  if (code == GP_OK || (code == GP_DUPLICATE && request.id == GP_MOVE)) return;
  throw UserError("gantry",
                  std::string(gp_message_name(request.id)) + " refused: " + ResultText(code),
                  code == GP_FAULT ? "read the fault bits with `acqctl status`, fix the cause, "
                                     "then clear the fault"
                                   : "");
}

void ProtocolGantry::Home() {
  gp_message m{};
  m.id = GP_HOME;
  m.body.HOME.axes_mask = 0x0F;
  Command(m);
}

void ProtocolGantry::MoveTo(const ArmAngles& t) {
  gp_message m{};
  m.id = GP_MOVE;
  m.body.MOVE = {next_command_id_++, gp_mdeg_from_rad(t.light_theta), gp_mdeg_from_rad(t.light_phi),
                 gp_mdeg_from_rad(t.camera_theta), gp_mdeg_from_rad(t.camera_phi)};
  Command(m);
}

void ProtocolGantry::Stop() {
  gp_message m{};
  m.id = GP_STOP;
  Command(m);
}

void ProtocolGantry::EmergencyStop() {
  gp_message m{};
  m.id = GP_ESTOP;
  Command(m);
}

GantryStatus ProtocolGantry::Status() {
  return ReadStatus();
}

GantryStatus ProtocolGantry::ReadStatus() {
  gp_message m{};
  m.id = GP_GET_STATUS;
  const gp_STATUS s = Request(m, GP_STATUS).body.STATUS;
  GantryStatus out;
  out.commanded = {gp_rad_from_mdeg(s.light_theta_cmd_mdeg), gp_rad_from_mdeg(s.light_phi_cmd_mdeg),
                   gp_rad_from_mdeg(s.camera_theta_cmd_mdeg),
                   gp_rad_from_mdeg(s.camera_phi_cmd_mdeg)};
  out.measured = {gp_rad_from_mdeg(s.light_theta_mdeg), gp_rad_from_mdeg(s.light_phi_mdeg),
                  gp_rad_from_mdeg(s.camera_theta_mdeg), gp_rad_from_mdeg(s.camera_phi_mdeg)};
  out.moving_mask = s.moving_mask;
  out.homed_mask = s.homed_mask;
  out.limit_mask = s.limit_mask;
  out.fault_bits = s.fault_bits;
  out.device_clock_ms = s.device_clock_ms;
  out.last_command_id = s.last_command_id;
  // A controller that restarted has a younger clock and has forgotten its home: whatever was
  // commanded before is void, and moving on would move from positions it does not know.
  // (A clock that wrapped after 49 days is far behind, not a little: not a reset.)
  const bool clock_restarted =
      s.device_clock_ms < last_clock_ms_ && last_clock_ms_ - s.device_clock_ms < 0x80000000u;
  const bool reset = clock_restarted || (homed_seen_ && !out.Homed());
  last_clock_ms_ = s.device_clock_ms;
  if (reset) {
    homed_seen_ = false;
    throw UserError("gantry",
                    "the controller was reset (its clock restarted at " +
                        std::to_string(s.device_clock_ms) + " ms and its axes are not homed)",
                    "home the gantry again before moving; captured frames are unaffected");
  }
  homed_seen_ = homed_seen_ || out.Homed();
  return out;
}

void ProtocolGantry::SetLight(bool on, double level) {
  if (!(level >= 0 && level <= 1)) throw UserError("light level", "must be in [0, 1]");
  gp_message m{};
  m.id = GP_LIGHT;
  m.body.LIGHT = {std::uint8_t(on), std::uint16_t(std::lround(level * 1000))};
  Command(m);
}

void ProtocolGantry::RenewLease(int ms) {
  gp_message m{};
  m.id = GP_LEASE;
  m.body.LEASE.duration_ms = std::uint16_t(std::clamp(ms, 0, 65535));
  Command(m);
}

void ProtocolGantry::ClearFaults(std::uint16_t bits) {
  gp_message m{};
  m.id = GP_CLEAR_FAULT;
  m.body.CLEAR_FAULT.fault_bits = bits;
  Command(m);
}

}  // namespace acq
