// Wall time of a stage, for the reports that say where a session's time went.
#pragma once

#include <chrono>

namespace acq {

using SteadyClock = std::chrono::steady_clock;

inline double SecondsSince(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

}  // namespace acq
