// The simulated gantry presented as a USB device (issue 5): umockdev puts a USB device with our
// descriptors (vendor interface, bulk OUT 0x01 and IN 0x81) into a testbed sysfs and /dev, and
// answers libusb's usbfs ioctls (SUBMITURB, REAPURB, DISCARDURB, control transfers for the
// string descriptors) from the simulated firmware. The host's real UsbTransport, unchanged,
// drives it through libusb. The process must run under umockdev's preload library
// (umockdev-wrapper, or LD_PRELOAD=libumockdev-preload.so.0); the constructor says so if not.
//
// Firmware time follows the wall clock times `time_scale`. Faults beyond the firmware's own:
// replies delayed, the device unplugged and plugged back (a new device number, as a real
// re-enumeration gives), and a firmware reset (the device re-enumerates with its state lost).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "sim/gantry_firmware.h"

namespace acq::sim {

struct EmulatedUsbOptions {
  std::uint16_t vendor_id = 0x1209, product_id = 0xACD0;
  std::string serial = "SIM-0001";
  double time_scale = 1.0;   // simulated seconds per wall-clock second
  double reply_delay_s = 0;  // wall-clock delay before a reply can be read (a slow device)
};

class EmulatedUsbGantry {
 public:
  EmulatedUsbGantry(FirmwareOptions firmware = {}, EmulatedUsbOptions usb = {});
  ~EmulatedUsbGantry();
  EmulatedUsbGantry(const EmulatedUsbGantry&) = delete;
  EmulatedUsbGantry& operator=(const EmulatedUsbGantry&) = delete;

  static bool UnderUmockdev();

  // The firmware, its clock brought up to date, under the lock the ioctl thread takes.
  template <class F>
  auto WithFirmware(F f) {
    std::lock_guard<std::mutex> lock(mutex_);
    Sync();
    return f(firmware_);
  }
  void SetReplyDelay(double seconds);
  void Unplug();         // every ioctl on the device fails with ENODEV; in-flight transfers end
  void Plug();           // back with its state intact (a cable replugged): a new device number
  void ResetFirmware();  // unplug, firmware state lost, plug back

  std::string devnode() const;
  int ioctls() const;  // how many usbfs requests were served (for the benchmark's record)

  // Called from umockdev's ioctl thread (public for the C callback only).
  bool HandleIoctl(void* client);

 private:
  struct Urb;
  void Sync();  // advances the firmware to the scaled wall clock
  void AddDevice();
  void CompleteInTransfers();
  void FailFlying(int status);

  FirmwareOptions firmware_options_;
  EmulatedUsbOptions usb_;
  mutable std::mutex mutex_;
  SimGantryFirmware firmware_;
  void* testbed_ = nullptr;  // UMockdevTestbed*
  void* handler_ = nullptr;  // UMockdevIoctlBase*
  std::chrono::steady_clock::time_point last_sync_;
  int devnum_ = 1;
  bool plugged_ = false;
  struct PendingReply {
    std::vector<std::uint8_t> bytes;
    std::chrono::steady_clock::time_point ready;
  };
  std::deque<PendingReply> replies_;
  std::deque<std::unique_ptr<Urb>> in_flight_, completed_;
  int ioctls_ = 0;
};

}  // namespace acq::sim
