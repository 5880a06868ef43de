// acq session repair: the catalog rebuilt from the frames' metadata (acq/session_repair.h).
#include <cstdio>

#include "acq/session_repair.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "core/error.h"

namespace acq::cli {

int SessionRepair(const Argv& argv) {
  const Args args("acq session repair", argv, {}, {});
  if (args.positionals().size() != 1)
    throw UserError("acq session repair", "give one session directory",
                    "acq session repair SESSION (the plan's output folder)");
  const std::string session = args.positionals()[0];
  const SessionRepairReport r = RepairSessionCatalog(session);
  std::printf(
      "%s: %d frames recorded from their metadata (%d were recorded already), %d "
      "bracket decisions restored (%d inferred from the exposures present)\n",
      session.c_str(), r.recorded, r.already_recorded, r.decisions_restored, r.decisions_inferred);
  for (const std::string& s : r.skipped) std::printf("  left alone: %s\n", s.c_str());
  std::printf("run acqd with the session's plan (%s/plan.yaml) to resume\n", session.c_str());
  return 0;
}

}  // namespace acq::cli
