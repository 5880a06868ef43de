// The one place mrcal's C headers enter C++: they lack extern "C" (docs/architecture.md,
// "Conventions"). Include this, never <mrcal.h> directly.
#pragma once

extern "C" {
#include <mrcal.h>
}
