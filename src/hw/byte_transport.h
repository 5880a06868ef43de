// A byte pipe to the gantry's microcontroller: USB bulk endpoints, a UART, a socket, or an
// in-process simulator. Framing and integrity are the protocol's job, not the transport's.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/error.h"

namespace acq {

// The device went away (unplugged, reset, powered off): the one error a caller may answer by
// reconnecting.
class TransportGone : public UserError {
 public:
  using UserError::UserError;
};

class ByteTransport {
 public:
  virtual ~ByteTransport() = default;
  virtual void Send(const std::uint8_t* data, std::size_t n) = 0;
  // Up to `capacity` bytes; 0 when nothing arrived within timeout_ms. Throws TransportGone when the
  // device is gone.
  virtual std::size_t Receive(std::uint8_t* data, std::size_t capacity, int timeout_ms) = 0;
  // After the device went away: waits up to timeout_ms for it to come back and reopens it.
  // False when it did not come back, or when this transport cannot reconnect.
  virtual bool Reconnect(int /*timeout_ms*/) { return false; }
};

}  // namespace acq
