// The words a session is made of (issue 21), each declared once with its one spelling: the
// capture steps (the catalog's rows, the frame files' names, the frames' `step` attribute) and
// the items the operator places under the gantry (the prompts, the simulated instrument). Text
// appears only where a step or an item is stored or shown; everywhere else they are these types.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace acq {

// In capture order (docs/session-and-plan.md, "Steps").
enum class Step {
  kIntrinsics,       // the chessboard held in a new pose for every capture: the lens
  kBoard,            // the chessboard flat on the sample plane at the sample's poses
  kBoardValidation,  // ... at the validation's poses
  kSample,           // the sample at the plan's directions
  kValidation,       // the sample at the validation directions (never reconstructed from)
  kSpectralon,       // the Spectralon at the sample's poses: the light's irradiance per view
  kSpectralonValidation,
  kChart,  // a colour camera's chart at the sample's first pose (core/colour_chart.h)
};
const char* ToString(Step s);  // "intrinsics", "board", "board_validation", ...
std::optional<Step> ParseStep(const std::string& text);
const std::vector<Step>& AllSteps();  // in capture order

// What lies under the gantry for a step.
enum class Item { kSample, kSpectralon, kBoard, kChart };
Item ItemOf(Step s);
// The step whose poses are `s`'s (sample, spectralon: sample; the validation ones: validation).
Step PosesOf(Step s);
// The board step that gives `s`'s poses their cam_from_sample (board or board_validation).
Step BoardStepFor(Step s);

// An item and, for a board held up for the intrinsics, which of its poses.
struct Placement {
  Item item = Item::kSample;
  int held_pose = 0;  // kBoard: 0 flat on the sample plane (the sample frame), K >= 1 the K-th held
  bool operator==(const Placement& o) const { return item == o.item && held_pose == o.held_pose; }
  bool operator!=(const Placement& o) const { return !(*this == o); }
};
std::string ToString(const Placement& p);  // "sample", "spectralon", "board", "board/3", "chart"
std::optional<Placement> ParsePlacement(const std::string& text);

}  // namespace acq
