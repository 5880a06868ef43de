#include <cstdio>

#include "brdf/directions.h"
#include "cli/args.h"
#include "cli/commands.h"

namespace acq::cli {

int DirectionsRandom(const Argv& argv) {
  const Args args("acq directions random", argv, {"n", "seed", "o"}, {});
  const int n = args.GetInt("n", 20);
  const int seed = args.GetInt("seed", 1);
  const std::string out = args.Required("o");
  WriteDirectionsTsv(RandomDirections(n, std::uint64_t(seed)), out,
                     std::to_string(n) +
                         " random directions (light and camera uniform over the "
                         "hemisphere), seed " +
                         std::to_string(seed) + "; Rusinkiewicz, degrees");
  std::printf("wrote %d directions to %s\n", n, out.c_str());
  return 0;
}

}  // namespace acq::cli
