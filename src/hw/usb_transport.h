// The gantry's USB link (issue 5): our vendor interface's bulk OUT and IN endpoints, through
// libusb. The device is found by VID, PID and (optionally) serial, as the plan names it. A device
// that disappears (unplugged, reset, re-enumerated) is reported as UserError; Reconnect() waits
// for it to come back and opens it afresh: a new libusb context, so the device list is read from
// the system again rather than from a cache that still holds the old device.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hw/byte_transport.h"

struct libusb_context;
struct libusb_device_handle;

namespace acq {

struct UsbDeviceId {
  std::uint16_t vendor_id = 0x1209;   // pid.codes, the open-source hardware vendor id
  std::uint16_t product_id = 0xACD0;  // our gantry controller
  std::string serial;                 // empty: the first matching device
  void Check() const;                 // throws UserError
  std::string Describe() const;       // "1209:acd0 serial GX-0001"
};

class UsbTransport : public ByteTransport {
 public:
  // Opens the device and claims its vendor interface; throws UserError naming the device and
  // what to check when it is absent, busy or not permitted.
  explicit UsbTransport(UsbDeviceId id);
  ~UsbTransport() override;
  UsbTransport(const UsbTransport&) = delete;
  UsbTransport& operator=(const UsbTransport&) = delete;

  void Send(const std::uint8_t* data, std::size_t n) override;
  std::size_t Receive(std::uint8_t* data, std::size_t capacity, int timeout_ms) override;
  bool Reconnect(int timeout_ms) override;

  const UsbDeviceId& id() const { return id_; }
  int reconnects() const { return reconnects_; }

 private:
  // Empty on success, else why the device could not be opened (for the error message).
  std::string Open();
  void Close();
  std::size_t TakeLeftover(std::uint8_t* data, std::size_t capacity);
  [[noreturn]] void Gone(const char* during, int libusb_error);

  UsbDeviceId id_;
  libusb_context* context_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  int interface_ = -1;
  std::uint8_t endpoint_out_ = 0, endpoint_in_ = 0;
  std::uint16_t in_packet_size_ = 64;
  std::vector<std::uint8_t> leftover_;  // received beyond what the caller had room for
  int reconnects_ = 0;
};

}  // namespace acq
