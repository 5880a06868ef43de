// The simulated instrument a plan describes (backend sim): its options, built from the plan in
// one place, for acqd, which builds the instrument, and for the scoring, which must rebuild
// the very sample the camera saw (its mixtures' tables). In session_truth, the part of the
// session library that links the simulator.
#pragma once

#include "acq/plan.h"
#include "sim/instrument.h"

namespace acq {

sim::InstrumentOptions InstrumentOptionsOf(const Plan& plan);

}  // namespace acq
