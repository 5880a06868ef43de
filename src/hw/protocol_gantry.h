// Gantry over our wire protocol (firmware_protocol/PROTOCOL.md), on any ByteTransport.
// Every request is retransmitted with the same sequence number until answered (a lost reply is
// safe to ask again for: a repeated MOVE carries the same command id, which the firmware
// acknowledges without moving twice). The handshake refuses firmware with another protocol
// version or schema.
//
// A device that vanishes is reopened (ByteTransport::Reconnect), the handshake is repeated and
// the state re-read, never assumed: when the controller was reset meanwhile (its clock restarted,
// its axes no longer homed) the request is not resent and the caller is told to home again.
#pragma once

#include <string>

#include "gantry_protocol.h"
#include "hw/byte_transport.h"
#include "hw/gantry.h"

namespace acq {

struct ProtocolGantryOptions {
  int reply_timeout_ms = 200;
  int attempts = 5;
  // How long to wait for a vanished device to come back before giving up. A reset controller
  // re-enumerates within about a second.
  int reconnect_timeout_ms = 5000;
};

class ProtocolGantry : public Gantry {
 public:
  // Performs the handshake; throws UserError on a mismatch or when nothing answers.
  ProtocolGantry(ByteTransport& transport, ProtocolGantryOptions options = {});

  void Home() override;
  void MoveTo(const ArmAngles& target) override;
  void Stop() override;
  void EmergencyStop() override;
  GantryStatus Status() override;
  void SetLight(bool on, double level) override;
  void RenewLease(int milliseconds) override;
  void ClearFaults(std::uint16_t bits) override;

  std::uint32_t firmware_build() const { return firmware_build_; }
  int retransmissions() const override { return retransmissions_; }
  int reconnects() const { return reconnects_; }

 private:
  gp_message Request(gp_message request, std::uint8_t reply_id);
  // One request with retransmissions, no reconnection; throws TransportGone.
  gp_message Exchange(const gp_message& request, std::uint8_t reply_id);
  void Handshake();
  void Reconnect(const TransportGone& why);
  GantryStatus ReadStatus();         // updates and checks what is known about resets
  void Command(gp_message request);  // expects RESULT OK (or DUPLICATE for MOVE)

  ByteTransport& transport_;
  ProtocolGantryOptions options_;
  gp_decoder decoder_;
  std::uint8_t sequence_ = 0;
  std::uint32_t next_command_id_ = 1;
  std::uint32_t firmware_build_ = 0;
  int retransmissions_ = 0;
  int reconnects_ = 0;
  bool homed_seen_ = false;  // the controller reported itself homed since the last reset
  std::uint32_t last_clock_ms_ = 0;
};

}  // namespace acq
