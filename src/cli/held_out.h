// Choosing the materials an evaluation reconstructs: the basis's held-out set among those the
// user names (or every one named, with --all-given). Shared by `basis eval` and
// `directions eval`.
#pragma once

#include <string>
#include <vector>

#include "brdf/basis.h"
#include "brdf/materials.h"
#include "cli/args.h"

namespace acq::cli {

std::vector<MaterialFile> SelectHeldOut(const BasisView& basis, const std::string& basis_path,
                                        const Args& args, const std::string& command);

// Above this condition number the sampled rows amplify observation noise badly (the seed's and
// our optimised sets of 20 sit far below it); users are warned, not stopped.
constexpr double kConditionWarning = 1e3;

}  // namespace acq::cli
