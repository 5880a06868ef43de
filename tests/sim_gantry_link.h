// An in-process ByteTransport to the simulated firmware, for tests: every exchange advances the
// firmware's simulated clock by a fixed latency, so polling loops see the arms move; requests
// can be dropped on the way in, and the link can be cut.
#pragma once

#include <deque>
#include <random>

#include "core/error.h"
#include "hw/byte_transport.h"
#include "sim/gantry_firmware.h"

namespace acq::test {

class SimGantryLink : public ByteTransport {
 public:
  explicit SimGantryLink(sim::SimGantryFirmware& firmware) : firmware_(firmware) {}
  double drop_request_probability = 0;
  bool unplugged = false;
  double latency_s = 0.005;

  void Send(const std::uint8_t* data, std::size_t n) override {
    if (unplugged) throw TransportGone("gantry", "USB device gone");
    std::uniform_real_distribution<double> u(0, 1);
    if (u(rng_) < drop_request_probability) return;
    std::vector<std::uint8_t> reply;
    firmware_.Receive(data, n, &reply);
    pending_.insert(pending_.end(), reply.begin(), reply.end());
  }
  std::size_t Receive(std::uint8_t* data, std::size_t capacity, int timeout_ms) override {
    if (unplugged) throw TransportGone("gantry", "USB device gone");
    if (pending_.empty()) {
      firmware_.Advance(timeout_ms / 1000.0);
      return 0;
    }
    firmware_.Advance(latency_s);
    std::size_t n = 0;
    while (n < capacity && !pending_.empty()) data[n++] = pending_.front(), pending_.pop_front();
    return n;
  }

 private:
  sim::SimGantryFirmware& firmware_;
  std::deque<std::uint8_t> pending_;
  std::mt19937_64 rng_{7};
};

}  // namespace acq::test
