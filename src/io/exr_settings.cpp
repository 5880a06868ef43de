#include "io/exr_settings.h"

#include <ImfThreading.h>

#include <mutex>
#include <thread>

namespace acq {

void UseExrThreads() {
  static std::once_flag once;
  std::call_once(once, [] {
    const unsigned cores = std::thread::hardware_concurrency();
    Imf::setGlobalThreadCount(int(cores > 0 ? cores : 1));
  });
}

}  // namespace acq
