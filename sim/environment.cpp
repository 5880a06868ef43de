#include "sim/environment.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "sim/usb_gantry_device.h"

namespace acq::sim {
namespace {

constexpr const char* kEnvironmentMark = "ACQD_SIM_ENVIRONMENT";

}  // namespace

bool EnvironmentReady() {
  return std::getenv(kEnvironmentMark) != nullptr && EmulatedUsbGantry::UnderUmockdev();
}

std::string ReexecIntoEnvironment(int argc, char** argv) {
  if (std::getenv(kEnvironmentMark))
    return "already re-executed, yet umockdev's preload library is not active";
  setenv(kEnvironmentMark, "1", 1);
  // unshare -rn: a user and network namespace (no root needed where unprivileged user
  // namespaces are allowed, Debian 12's default); then lo up with 127.0.0.2, and the preload.
  std::vector<char*> args;
  std::string script =
      "ip link set lo up && ip addr add 127.0.0.2/8 dev lo && "
      "exec env LD_PRELOAD=libumockdev-preload.so.0${LD_PRELOAD:+:$LD_PRELOAD} \"$@\"";
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  args.push_back(const_cast<char*>("unshare"));
  args.push_back(const_cast<char*>("-rn"));
  args.push_back(const_cast<char*>("sh"));
  args.push_back(const_cast<char*>("-c"));
  args.push_back(script.data());
  args.push_back(const_cast<char*>("acqd-sim"));
  args.push_back(const_cast<char*>(self.c_str()));
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execvp("unshare", args.data());
  return "cannot run unshare (util-linux) to make the simulated instrument's network namespace";
}

}  // namespace acq::sim
