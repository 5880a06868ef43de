// Light/view direction sets, as TSV in degrees (like data/directions/seed_directions_20.tsv):
// '#' comment lines, a header naming the columns theta_h, theta_d, phi_d, then one direction a
// line in Rusinkiewicz coordinates (phi_h is free for isotropic BRDFs). Further columns (the
// writer adds the arm angles for phi_h = 0, camera on the smaller zenith) are ignored on read.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/merl_grid.h"

namespace acq {

struct Direction {
  RusinkiewiczAngles angles;  // radians, phi_h = 0
  std::string where;          // "file:line" it came from, for messages
};

// Throws UserError with file:line on a malformed line, a value out of range, a direction
// below the horizon or in a masked bin, and on an empty set.
std::vector<Direction> ReadDirectionsTsv(const std::string& path);
void WriteDirectionsTsv(const std::vector<Direction>& directions, const std::string& path,
                        const std::string& comment);

// n directions with light and camera each uniform over the hemisphere by solid angle, kept only
// when their MERL bin is valid. Deterministic for a given seed.
std::vector<Direction> RandomDirections(int n, std::uint64_t seed);

// The MERL bins of a set of directions.
std::vector<std::size_t> BinsOf(const std::vector<Direction>& directions);

}  // namespace acq
