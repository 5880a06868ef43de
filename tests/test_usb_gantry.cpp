// The USB gantry driver, unchanged, against the simulated firmware presented by umockdev as a
// USB device: the whole host path (ProtocolGantry -> UsbTransport -> libusb -> usbfs ioctls) runs
// as it would against the real controller. Run under umockdev-wrapper (meson does).
#include <catch2/catch.hpp>

#include <chrono>

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
