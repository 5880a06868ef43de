// The USB gantry driver, unchanged, against the simulated firmware presented by umockdev as a
// USB device: the whole host path (ProtocolGantry -> UsbTransport -> libusb -> usbfs ioctls) runs
// as it would against the real controller. Run under umockdev-wrapper (meson does).
#include <catch2/catch.hpp>

#include <chrono>
#include <thread>

#include "core/angles.h"
#include "core/error.h"
#include "hw/protocol_gantry.h"
#include "hw/usb_transport.h"
#include "sim/usb_gantry_device.h"

using namespace acq;

namespace {

const ArmAngles kTarget{DegToRad(40), DegToRad(-30), DegToRad(20), DegToRad(150)};
const ArmAngles kOther{DegToRad(60), DegToRad(10), DegToRad(35), DegToRad(-120)};

// Simulated time runs 5x the wall clock: a 4 s move takes under a second of the test's time
// while USB round trips (~0.1 ms here) stay far shorter than any firmware timing.
sim::EmulatedUsbOptions FastDevice() {
  sim::EmulatedUsbOptions o;
  o.time_scale = 5;
  return o;
}

UsbDeviceId SimId() {
  UsbDeviceId id;
  id.serial = "SIM-0001";
  return id;
}

int ExecutedMoves(sim::EmulatedUsbGantry& device) {
  return device.WithFirmware([](sim::SimGantryFirmware& f) { return f.executed_moves(); });
}

void RequireAt(const GantryStatus& s, const ArmAngles& t) {
  const double mdeg = DegToRad(0.001);  // the protocol's resolution
  REQUIRE(s.measured.light_theta == Approx(t.light_theta).margin(mdeg));
  REQUIRE(s.measured.light_phi == Approx(t.light_phi).margin(mdeg));
  REQUIRE(s.measured.camera_theta == Approx(t.camera_theta).margin(mdeg));
  REQUIRE(s.measured.camera_phi == Approx(t.camera_phi).margin(mdeg));
}

// A simulated gantry on emulated USB, the real driver connected to it, homed and at kTarget.
struct AtTarget {
  sim::EmulatedUsbGantry device{{}, FastDevice()};
  UsbTransport transport{SimId()};
  ProtocolGantry gantry{transport};
  AtTarget() {
    gantry.Home();
    MoveAndWait(gantry, kTarget, 20);
  }
};

double SecondsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

TEST_CASE("usb: the driver finds, homes and moves the simulated gantry through libusb", "[usb]") {
  REQUIRE(sim::EmulatedUsbGantry::UnderUmockdev());
  sim::EmulatedUsbGantry device({}, FastDevice());
  UsbTransport transport(SimId());
  ProtocolGantry gantry(transport);
  CHECK(gantry.firmware_build() == 1);
  gantry.Home();
  MoveAndWait(gantry, kTarget, TrapezoidProfile{DegToRad(30), DegToRad(60)}, 0.5);
  RequireAt(gantry.Status(), kTarget);
  CHECK(ExecutedMoves(device) == 1);
  CHECK(device.ioctls() > 10);  // it really went through usbfs
}

TEST_CASE("usb: a wrong serial or an absent device is refused with what to check", "[usb]") {
  sim::EmulatedUsbGantry device({}, FastDevice());
  UsbDeviceId wrong = SimId();
  wrong.serial = "GX-9999";
  CHECK_THROWS_WITH(UsbTransport(wrong),
                    Catch::Contains("serial is not GX-9999") && Catch::Contains("lsusb -v"));
  UsbDeviceId other = SimId();
  other.product_id = 0x0001;
  CHECK_THROWS_WITH(UsbTransport(other), Catch::Contains("1209:0001") &&
                                             Catch::Contains("no such device") &&
                                             Catch::Contains("cable"));
}

TEST_CASE("usb: lost, corrupted and late replies are retransmitted; no move runs twice", "[usb]") {
  sim::EmulatedUsbGantry device({}, FastDevice());
  device.WithFirmware([](sim::SimGantryFirmware& f) {
    f.faults.drop_reply_probability = 0.3;
    f.faults.corrupt_reply_probability = 0.2;
  });
  UsbTransport transport(SimId());
  ProtocolGantryOptions o;
  o.attempts = 20;  // with ~45% of replies lost, 20 tries all fail with p < 1e-6
  o.reply_timeout_ms = 20;
  ProtocolGantry gantry(transport, o);
  gantry.Home();
  MoveAndWait(gantry, kTarget, 20);
  // Replies now arrive after 30 ms, past the 20 ms timeout: the late answer to the first copy
  // (same sequence number) is taken, later duplicates are ignored as stale.
  device.SetReplyDelay(0.030);
  MoveAndWait(gantry, kOther, 20);
  device.SetReplyDelay(0);
  RequireAt(gantry.Status(), kOther);
  CHECK(gantry.retransmissions() > 0);
  CHECK(ExecutedMoves(device) == 2);
}

TEST_CASE("usb: a stalled axis or a tripped limit stops the arms with a clear error", "[usb]") {
  AtTarget f;
  auto& [device, transport, gantry] = f;
  device.WithFirmware([](sim::SimGantryFirmware& f) { f.faults.stalled_axis = 2; });
  CHECK_THROWS_WITH(MoveAndWait(gantry, kOther, 20), Catch::Contains("fault during the move"));
  GantryStatus s = gantry.Status();
  CHECK_FALSE(s.Moving());
  CHECK((s.fault_bits & GP_FAULT_BIT_STALL) != 0);
  CHECK_THROWS_WITH(gantry.MoveTo(kOther), Catch::Contains("fault is latched"));
  device.WithFirmware([](sim::SimGantryFirmware& f) { f.faults.stalled_axis = -1; });
  gantry.ClearFaults(0xFFFF);
  device.WithFirmware([](sim::SimGantryFirmware& f) { f.faults.trip_limit = true; });
  CHECK_THROWS_WITH(MoveAndWait(gantry, kOther, 20), Catch::Contains("fault during the move"));
  CHECK((gantry.Status().fault_bits & GP_FAULT_BIT_LIMIT) != 0);
  gantry.ClearFaults(0xFFFF);
  MoveAndWait(gantry, kOther, 20);
  RequireAt(gantry.Status(), kOther);
}

TEST_CASE("usb: a move whose reply is lost to an unplug is resent after the replug, once",
          "[usb]") {
  AtTarget f;
  auto& [device, transport, gantry] = f;
  // The MOVE reaches the firmware and starts, its reply is held back, and the cable is pulled
  // before it can be read: the host sees the device vanish mid-request.
  gantry.RenewLease(5000);
  device.SetReplyDelay(0.5);
  std::thread cable([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(60));
    device.Unplug();
    device.SetReplyDelay(0);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    device.Plug();
  });
  const auto start = std::chrono::steady_clock::now();
  gantry.MoveTo(kOther);  // reconnects, re-handshakes, re-reads state, resends the same MOVE
  cable.join();
  CHECK(SecondsSince(start) < 3);
  CHECK(gantry.reconnects() == 1);
  CHECK(transport.reconnects() == 1);
  GantryStatus s = gantry.Status();
  while (s.Moving()) gantry.RenewLease(2000), s = gantry.Status();
  CHECK(s.fault_bits == 0);
  RequireAt(s, kOther);
  CHECK(ExecutedMoves(device) == 2);  // the resent MOVE was a duplicate, not a second move
}

TEST_CASE("usb: a device that does not come back ends in a clear error, never a hang", "[usb]") {
  sim::EmulatedUsbGantry device({}, FastDevice());
  UsbTransport transport(SimId());
  ProtocolGantryOptions o;
  o.reconnect_timeout_ms = 1000;
  ProtocolGantry gantry(transport, o);
  gantry.Home();
  device.Unplug();
  const auto start = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(gantry.Status(), Catch::Contains("device gone") &&
                                         Catch::Contains("did not come back within 1.00 s") &&
                                         Catch::Contains("cable"));
  CHECK(SecondsSince(start) < 3);  // the reconnect timeout, plus a libusb start or two
}

TEST_CASE("usb: a controller reset is detected after the reconnect; homing again recovers",
          "[usb]") {
  AtTarget f;
  auto& [device, transport, gantry] = f;
  const int moves_before = ExecutedMoves(device);
  device.ResetFirmware();
  CHECK_THROWS_WITH(gantry.MoveTo(kOther), Catch::Contains("controller was reset") &&
                                               Catch::Contains("home the gantry again"));
  CHECK(ExecutedMoves(device) == moves_before);  // the MOVE was not sent to a lost state
  gantry.Home();
  MoveAndWait(gantry, kOther, 20);
  RequireAt(gantry.Status(), kOther);
}
