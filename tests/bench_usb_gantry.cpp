// Benchmark (issue 5): round-trip latency of a status request and command throughput through
// the whole USB path (ProtocolGantry -> UsbTransport -> libusb -> usbfs ioctls answered by the
// simulated firmware behind umockdev), and the same requests over the in-process link, which
// isolates what the protocol and the firmware cost from what the USB path costs.
//
//   umockdev-wrapper build/tests/bench_usb_gantry [requests=5000] [out.csv]
//
// umockdev carries every ioctl over a socket to its handler thread, so these figures bound our
// host code and libusb from above; a real controller adds the bus's own latency (a high-speed
// bulk round trip is a few 125 us microframes) and its firmware's.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "hw/protocol_gantry.h"
#include "hw/usb_transport.h"
#include "sim/usb_gantry_device.h"
#include "sim_gantry_link.h"

using namespace acq;
using Clock = std::chrono::steady_clock;

namespace {

struct Figures {
  double median_us, p95_us, p99_us, max_us, status_per_s, commands_per_s;
};

double Percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

Figures Measure(Gantry& gantry, int requests, std::vector<double>* latencies_us) {
  for (int i = 0; i < 100; ++i) gantry.Status();  // warm up
  latencies_us->clear();
  const auto start = Clock::now();
  for (int i = 0; i < requests; ++i) {
    const auto t = Clock::now();
    gantry.Status();
    latencies_us->push_back(std::chrono::duration<double, std::micro>(Clock::now() - t).count());
  }
  const double status_s = std::chrono::duration<double>(Clock::now() - start).count();
  // Commands answered with RESULT: the light level, the one a session sends most besides
  // status and lease.
  const auto command_start = Clock::now();
  for (int i = 0; i < requests; ++i) gantry.SetLight(true, (i % 1000) / 1000.0);
  const double command_s = std::chrono::duration<double>(Clock::now() - command_start).count();
  return {Percentile(*latencies_us, 0.5),
          Percentile(*latencies_us, 0.95),
          Percentile(*latencies_us, 0.99),
          *std::max_element(latencies_us->begin(), latencies_us->end()),
          requests / status_s,
          requests / command_s};
}

void Print(const char* path, const Figures& f) {
  std::printf("%-34s %9.1f %9.1f %9.1f %9.1f %12.0f %12.0f\n", path, f.median_us, f.p95_us,
              f.p99_us, f.max_us, f.status_per_s, f.commands_per_s);
}

}  // namespace

int main(int argc, char** argv) {
  const int requests = argc > 1 ? std::max(100, std::atoi(argv[1])) : 5000;
  const std::string csv = argc > 2 ? argv[2] : "";
  if (!sim::EmulatedUsbGantry::UnderUmockdev()) {
    std::fprintf(stderr, "run under umockdev-wrapper: umockdev-wrapper %s\n", argv[0]);
    return 2;
  }
  std::printf("%d requests each; latency of GET_STATUS -> STATUS in microseconds\n", requests);
  std::printf("%-34s %9s %9s %9s %9s %12s %12s\n", "path", "median", "p95", "p99", "max",
              "status/s", "commands/s");
  std::vector<double> usb_us, link_us;
  sim::EmulatedUsbGantry device;
  UsbTransport transport(UsbDeviceId{0x1209, 0xACD0, "SIM-0001"});
  ProtocolGantry usb(transport);
  Print("USB (libusb, usbfs via umockdev)", Measure(usb, requests, &usb_us));
  sim::SimGantryFirmware firmware;
  test::SimGantryLink link(firmware);
  link.latency_s = 0;
  ProtocolGantry in_process(link);
  Print("in-process link (no USB)", Measure(in_process, requests, &link_us));
  std::printf("usbfs requests served: %d (%.1f per exchange)\n", device.ioctls(),
              device.ioctls() / (2.0 * requests + 200 + 2));
  if (!csv.empty()) {
    std::ofstream out(csv);
    out << "path,latency_us\n";
    for (double v : usb_us) out << "usb," << v << "\n";
    for (double v : link_us) out << "in_process," << v << "\n";
    std::printf("latencies written to %s\n", csv.c_str());
  }
  return 0;
}
