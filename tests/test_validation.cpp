#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include "acq/validation.h"

using namespace acq;

TEST_CASE("a validation view's relative RMS split by label", "[validation]") {
  // Four pixels, two labels and one unlabelled: label 0 predicts twice its capture (relative
  // RMS 1), label 1 exactly (0); the unlabelled pixel and a label with no pixel count nowhere.
  ValidationResult r;
  r.predicted = {4, 1, {2, 2, 2, 4, 4, 4, 1, 1, 1, 9, 9, 9}};
  r.captured = {4, 1, {1, 1, 1, 2, 2, 2, 1, 1, 1, 1, 1, 1}};
  const std::vector<double> by = RelativeRmsByLabel(r, {0, 0, 1, -1}, 3);
  REQUIRE(by.size() == 3);
  CHECK(by[0] == Approx(1.0));
  CHECK(by[1] == 0.0);
  CHECK(by[2] == 0.0);
  CHECK_THROWS_AS(RelativeRmsByLabel(r, {0, 0, 1}, 3), std::invalid_argument);
}
