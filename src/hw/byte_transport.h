// A byte pipe to the gantry's microcontroller: USB bulk endpoints, a UART, a socket, or an
// in-process simulator. Framing and integrity are the protocol's job, not the transport's.
#pragma once

#include <cstddef>
#include <cstdint>

namespace acq {

class ByteTransport {
 public:
  virtual ~ByteTransport() = default;
  virtual void Send(const std::uint8_t* data, std::size_t n) = 0;
  // Up to `capacity` bytes; 0 when nothing arrived within timeout_ms. Throws UserError when the
  // device is gone.
  virtual std::size_t Receive(std::uint8_t* data, std::size_t capacity, int timeout_ms) = 0;
};

}  // namespace acq
