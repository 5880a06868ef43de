#include "core/session_vocabulary.h"

#include <array>
#include <cstdlib>
#include <iterator>

namespace acq {
namespace {

struct StepName {
  Step step;
  const char* name;
};
constexpr std::array<StepName, 8> kSteps{{
    {Step::kIntrinsics, "intrinsics"},
    {Step::kBoard, "board"},
    {Step::kBoardValidation, "board_validation"},
    {Step::kSample, "sample"},
    {Step::kValidation, "validation"},
    {Step::kSpectralon, "spectralon"},
    {Step::kSpectralonValidation, "spectralon_validation"},
    {Step::kChart, "chart"},
}};

constexpr const char* kItemNames[] = {"sample", "spectralon", "board", "chart"};

}  // namespace

const char* ToString(Step s) {
  for (const StepName& n : kSteps)
    if (n.step == s) return n.name;
  return "?";
}

std::optional<Step> ParseStep(const std::string& text) {
  for (const StepName& n : kSteps)
    if (text == n.name) return n.step;
  return std::nullopt;
}

const std::vector<Step>& AllSteps() {
  static const std::vector<Step> all = [] {
    std::vector<Step> v;
    for (const StepName& n : kSteps) v.push_back(n.step);
    return v;
  }();
  return all;
}

Item ItemOf(Step s) {
  switch (s) {
    case Step::kSample:
    case Step::kValidation:
      return Item::kSample;
    case Step::kSpectralon:
    case Step::kSpectralonValidation:
      return Item::kSpectralon;
    case Step::kChart:
      return Item::kChart;
    default:
      return Item::kBoard;
  }
}

Step PosesOf(Step s) {
  switch (s) {
    case Step::kBoardValidation:
    case Step::kValidation:
    case Step::kSpectralonValidation:
      return Step::kValidation;
    case Step::kIntrinsics:
      return Step::kIntrinsics;
    default:
      return Step::kSample;
  }
}

Step BoardStepFor(Step s) {
  return PosesOf(s) == Step::kValidation ? Step::kBoardValidation : Step::kBoard;
}

std::string ToString(const Placement& p) {
  std::string text = kItemNames[int(p.item)];
  if (p.item == Item::kBoard && p.held_pose > 0) text += "/" + std::to_string(p.held_pose);
  return text;
}

std::optional<Placement> ParsePlacement(const std::string& text) {
  const std::size_t slash = text.find('/');
  const std::string head = text.substr(0, slash);
  for (int i = 0; i < int(std::size(kItemNames)); ++i) {
    if (head != kItemNames[i]) continue;
    Placement p{Item(i), 0};
    if (slash == std::string::npos) return p;
    if (p.item != Item::kBoard) return std::nullopt;
    char* end = nullptr;
    const long k = std::strtol(text.c_str() + slash + 1, &end, 10);
    if (end == text.c_str() + slash + 1 || *end != '\0' || k < 1 || k > 1000000)
      return std::nullopt;
    p.held_pose = int(k);
    return p;
  }
  return std::nullopt;
}

}  // namespace acq
