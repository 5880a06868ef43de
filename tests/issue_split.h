// The material split of issue 2, used by the accuracy tests: every tenth material by sorted
// name from the sixth held out (10), the basis from the other 90 with the default 64 components.
#pragma once

#include "brdf/basis.h"
#include "test_helpers.h"

namespace acq::test {

inline MaterialSplit IssueSplit() {
  HoldOut h;
  h.every = 10;
  h.offset = 5;
  return SplitMaterials(ListMaterials({DataPath("nbrdf/merl")}), h);
}

inline BasisData IssueBasis(const MaterialSplit& split) {
  BasisOptions o;
  o.progress = false;
  return BuildBasis(split, o);
}

}  // namespace acq::test
