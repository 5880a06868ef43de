// A resumed session's frames must be of the poses this run plans (session/capture.h,
// PoseMismatch): a planner that visits the directions in another order would otherwise count one
// direction's frames as another's.
#include <catch2/catch.hpp>

#include "core/angles.h"
#include "core/error.h"
#include "hw/frame_file.h"
#include "session/capture.h"

using namespace acq;

TEST_CASE("a resumed pose must be where its frames were taken", "[session]") {
  PlannedPose planned{3, {DegToRad(30), DegToRad(-170), DegToRad(25), DegToRad(10)}, 1.0};
  std::map<std::string, std::string> frame{
      {"arms_commanded_deg", ArmAnglesAttribute(planned.arms)}};
  CHECK(PoseMismatch(planned, frame, "frame.exr").empty());
  // Within the attribute's thousandth of a degree: the same pose.
  planned.arms.camera_theta += DegToRad(0.0015);
  CHECK(PoseMismatch(planned, frame, "frame.exr").empty());
  // The same direction at another azimuth (a planner that spreads the half vectors, or one that
  // no longer wraps), or another direction: refused, both poses named.
  planned.arms.light_phi = DegToRad(170);
  const std::string why = PoseMismatch(planned, frame, "frame.exr");
  CHECK_THAT(why, Catch::Contains("30.000 -170.000") && Catch::Contains("30.000 170.000"));
  // Frames written before commanded arms were recorded: nothing to compare.
  CHECK(PoseMismatch(planned, {{"direction", "x.tsv:3"}}, "frame.exr").empty());
  // A damaged attribute is an error naming it, not a silent pass.
  CHECK_THROWS_AS(PoseMismatch(planned, {{"arms_commanded_deg", "30 -170"}}, "frame.exr"),
                  UserError);
}
