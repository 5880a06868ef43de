// The session's vocabulary (core/session_vocabulary.h): every step and placement spelled once,
// read back as written, anything else refused.
#include <catch2/catch.hpp>

#include "core/session_vocabulary.h"

using namespace acq;

TEST_CASE("vocabulary: every step and placement reads back as written; others are refused",
          "[core]") {
  REQUIRE(AllSteps().size() == 8);
  for (const Step s : AllSteps()) {
    CHECK(ParseStep(ToString(s)) == s);
    // A step's placement, and the board step that calibrates its poses.
    CHECK(ItemOf(BoardStepFor(s)) == Item::kBoard);
  }
  CHECK(ItemOf(Step::kValidation) == Item::kSample);
  CHECK(ItemOf(Step::kSpectralonValidation) == Item::kSpectralon);
  CHECK(BoardStepFor(Step::kSpectralonValidation) == Step::kBoardValidation);
  CHECK(BoardStepFor(Step::kSpectralon) == Step::kBoard);
  CHECK(ItemOf(Step::kChart) == Item::kChart);
  CHECK(BoardStepFor(Step::kChart) == Step::kBoard);  // at the sample's first pose
  CHECK(ToString(Step::kChart) == std::string("chart"));
  for (const char* bad : {"", "Sample", "sample ", "board/", "reconstruction"})
    CHECK_FALSE(ParseStep(bad));

  for (const Placement p :
       {Placement{Item::kSample, 0}, Placement{Item::kSpectralon, 0}, Placement{Item::kBoard, 0},
        Placement{Item::kBoard, 12}, Placement{Item::kChart, 0}})
    CHECK(ParsePlacement(ToString(p)) == p);
  CHECK(ToString(Placement{Item::kBoard, 3}) == "board/3");
  for (const char* bad :
       {"board/0", "board/-1", "board/x", "board/3x", "sample/2", "chart/1", "", "cloth"})
    CHECK_FALSE(ParsePlacement(bad));
}
