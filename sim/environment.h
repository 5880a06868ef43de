// The environment the simulated instrument needs (issue 8): umockdev's preload library (the
// emulated USB gantry) and a loopback that carries 127.0.0.2 (the GigE Vision camera), in a
// private network namespace. acqd re-executes itself inside both when the plan asks for the sim
// backend.
#pragma once

#include <string>

namespace acq::sim {

// True when this process can host the simulated instrument.
bool EnvironmentReady();
// Replaces this process with itself inside a private network namespace with 127.0.0.2 on its
// loopback and umockdev's preload library; returns only when that cannot be done (with why).
std::string ReexecIntoEnvironment(int argc, char** argv);

}  // namespace acq::sim
