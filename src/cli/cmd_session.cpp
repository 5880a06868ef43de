// acq session repair: the catalog rebuilt from the frames' metadata (acq/session_repair.h);
// acq session process: the processing run again (session/reprocess.h).
#include <cstdio>

#include "acq/session_repair.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/seconds_since.h"
#include "session/report.h"
#include "session/reprocess.h"
#include "session/truth_score.h"

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

int SessionProcess(const Argv& argv) {
  const Args args("acq session process", argv, {"from", "set", "o"}, {});
  if (args.positionals().size() != 1)
    throw UserError("acq session process", "give one session directory",
                    "acq session process SESSION [--from STAGE] [--set KEY=VALUE] [-o NEW]");
  ReprocessOptions options;
  options.session = args.positionals()[0];
  const std::string from = args.Get("from", ToString(options.from));
  const std::optional<ProcessStage> stage = ParseProcessStage(from);
  if (!stage)
    throw UserError("--from " + from, "unknown stage", "use hdr, calibration or reconstruction");
  options.from = *stage;
  options.settings = args.Values("set");
  options.output = args.Get("o");
  const auto start = SteadyClock::now();
  const ReprocessResult r = ReprocessSession(options);
  for (const std::string& change : r.processing_changes)
    std::printf("processing setting changed: %s\n", change.c_str());
  SessionReport report;
  report.plan = r.plan.path;
  report.colour_filter = CfaOf(r.plan.camera.settings.pixel_format);
  report.backend = std::string("acq session process (") + BackendName(r.plan.backend) + ")";
  report.session = r.plan.output;
  report.process = r.process;
  report.captured = false;
  // A simulated session scored as acqd scored it: what was made of it against its truth.
  if (HasGroundTruth(r.plan.output)) {
    const auto scoring_start = SteadyClock::now();
    ScoreAgainstGroundTruth(r.plan, r.plan.output, &report);
    report.scoring_s = SecondsSince(scoring_start);
  }
  report.wall_s = SecondsSince(start);
  WriteReport(report, r.plan.output);
  std::printf("%s\nmap: %s/svbrdf.exr; report: %s/report.txt and report.json\n",
              report.Text().c_str(), r.plan.output.c_str(), r.plan.output.c_str());
  return 0;
}

}  // namespace acq::cli
