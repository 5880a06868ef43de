#include "hw/usb_transport.h"

#include <libusb.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

#include "core/error.h"

namespace acq {
namespace {

constexpr std::uint8_t kVendorClass = 0xFF;
constexpr int kSendTimeoutMs = 1000;  // an OUT transfer of one frame takes well under 1 ms

std::string Hex4(std::uint16_t v) {
  char s[8];
  std::snprintf(s, sizeof s, "%04x", v);
  return s;
}

// The vendor interface: class 0xFF with one bulk OUT and one bulk IN endpoint.
bool FindBulkInterface(libusb_device* device, int* interface, std::uint8_t* out, std::uint8_t* in,
                       std::uint16_t* in_packet) {
  libusb_config_descriptor* config = nullptr;
  if (libusb_get_active_config_descriptor(device, &config) != 0) return false;
  bool found = false;
  for (int i = 0; i < config->bNumInterfaces && !found; ++i) {
    if (config->interface[i].num_altsetting < 1) continue;
    const libusb_interface_descriptor& alt = config->interface[i].altsetting[0];
    if (alt.bInterfaceClass != kVendorClass) continue;
    std::uint8_t o = 0, n = 0;
    std::uint16_t packet = 0;
    for (int e = 0; e < alt.bNumEndpoints; ++e) {
      const libusb_endpoint_descriptor& ep = alt.endpoint[e];
      if ((ep.bmAttributes & 0x03) != LIBUSB_TRANSFER_TYPE_BULK) continue;
      if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN)
        n = ep.bEndpointAddress, packet = ep.wMaxPacketSize;
      else
        o = ep.bEndpointAddress;
    }
    if (o && n) *interface = alt.bInterfaceNumber, *out = o, *in = n, *in_packet = packet;
    found = o && n;
  }
  libusb_free_config_descriptor(config);
  return found;
}

}  // namespace

void UsbDeviceId::Check() const {
  if (vendor_id == 0 || product_id == 0)
    throw UserError("gantry USB id", "vendor and product id must be non-zero",
                    "give them as in `lsusb`, e.g. 1209:acd0");
}

std::string UsbDeviceId::Describe() const {
  return Hex4(vendor_id) + ":" + Hex4(product_id) +
         (serial.empty() ? std::string() : " serial " + serial);
}

UsbTransport::UsbTransport(UsbDeviceId id) : id_(std::move(id)) {
  id_.Check();
  const std::string why = Open();
  if (!why.empty())
    throw UserError("gantry USB " + id_.Describe(), why.substr(0, why.find('|')),
                    why.substr(why.find('|') + 1));
}

UsbTransport::~UsbTransport() {
  Close();
}

std::string UsbTransport::Open() {
  if (const int r = libusb_init(&context_); r != 0) {
    context_ = nullptr;
    return std::string("libusb could not start: ") + libusb_strerror(r) + "|";
  }
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(context_, &list);
  std::string why =
      "no such device on the USB bus|check the cable and the gantry's power, and "
      "the ids in the plan against `lsusb`";
  for (ssize_t i = 0; i < count && !handle_; ++i) {
    libusb_device_descriptor d;
    if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
    if (d.idVendor != id_.vendor_id || d.idProduct != id_.product_id) continue;
    libusb_device_handle* h = nullptr;
    if (const int r = libusb_open(list[i], &h); r != 0) {
      why = std::string("found but cannot be opened: ") + libusb_strerror(r) +
            (r == LIBUSB_ERROR_ACCESS ? "|install tools/udev/70-acq-gantry.rules or run as a "
                                        "member of the plugdev group"
                                      : "|");
      continue;
    }
    if (!id_.serial.empty()) {
      unsigned char serial[128] = {};
      const int n = d.iSerialNumber ? libusb_get_string_descriptor_ascii(h, d.iSerialNumber, serial,
                                                                         sizeof serial - 1)
                                    : 0;
      if (n <= 0 || id_.serial != reinterpret_cast<const char*>(serial)) {
        why = "a device with these ids is present but its serial is not " + id_.serial +
              "|check the serial in the plan (lsusb -v shows iSerial)";
        libusb_close(h);
        continue;
      }
    }
    if (!FindBulkInterface(list[i], &interface_, &endpoint_out_, &endpoint_in_, &in_packet_size_)) {
      why =
          "the device has no vendor interface with bulk endpoints|is it our gantry "
          "controller, with its firmware flashed?";
      libusb_close(h);
      continue;
    }
    libusb_set_auto_detach_kernel_driver(h, 1);  // not supported everywhere; harmless then
    if (const int r = libusb_claim_interface(h, interface_); r != 0) {
      why = std::string("its interface cannot be claimed: ") + libusb_strerror(r) +
            (r == LIBUSB_ERROR_BUSY ? "|another program holds it; is another acqd running?" : "|");
      libusb_close(h);
      continue;
    }
    handle_ = h;
  }
  libusb_free_device_list(list, 1);
  if (handle_) return {};
  Close();
  return why;
}

void UsbTransport::Close() {
  leftover_.clear();
  if (handle_) {
    libusb_release_interface(handle_, interface_);  // fails harmlessly on a vanished device
    libusb_close(handle_);
    handle_ = nullptr;
  }
  if (context_) libusb_exit(context_);
  context_ = nullptr;
}

void UsbTransport::Gone(const char* during, int libusb_error) {
  throw TransportGone(
      "gantry USB " + id_.Describe(),
      std::string("device gone during ") + during + " (" + libusb_error_name(libusb_error) + ")",
      "check the cable and the gantry's power; without the host renewing its lease "
      "the firmware stops the arms");
}

void UsbTransport::Send(const std::uint8_t* data, std::size_t n) {
  if (!handle_) Gone("send", LIBUSB_ERROR_NO_DEVICE);
  int done = 0;
  const int r = libusb_bulk_transfer(handle_, endpoint_out_, const_cast<std::uint8_t*>(data),
                                     int(n), &done, kSendTimeoutMs);
  // A timed-out or short send loses (part of) a frame: the firmware's decoder resyncs and the
  // protocol retransmits, so only a vanished device is an error here.
  if (r == LIBUSB_ERROR_NO_DEVICE || r == LIBUSB_ERROR_IO) Gone("send", r);
}

std::size_t UsbTransport::Receive(std::uint8_t* data, std::size_t capacity, int timeout_ms) {
  if (!handle_) Gone("receive", LIBUSB_ERROR_NO_DEVICE);
  if (!leftover_.empty()) return TakeLeftover(data, capacity);
  // Whole packets: a buffer that is not a multiple of the packet size can overflow.
  std::vector<std::uint8_t> buffer(std::max<std::size_t>(
      in_packet_size_, (capacity + in_packet_size_ - 1) / in_packet_size_ * in_packet_size_));
  int got = 0;
  const int r = libusb_bulk_transfer(handle_, endpoint_in_, buffer.data(), int(buffer.size()), &got,
                                     std::max(1, timeout_ms));  // 0 would wait forever
  if (r != 0 && r != LIBUSB_ERROR_TIMEOUT && r != LIBUSB_ERROR_OVERFLOW) Gone("receive", r);
  leftover_.assign(buffer.begin(), buffer.begin() + got);
  return TakeLeftover(data, capacity);
}

std::size_t UsbTransport::TakeLeftover(std::uint8_t* data, std::size_t capacity) {
  const std::size_t n = std::min(leftover_.size(), capacity);
  std::memcpy(data, leftover_.data(), n);
  leftover_.erase(leftover_.begin(), leftover_.begin() + std::ptrdiff_t(n));
  return n;
}

bool UsbTransport::Reconnect(int timeout_ms) {
  Close();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    if (Open().empty()) {
      ++reconnects_;
      return true;
    }
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace acq
