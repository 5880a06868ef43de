// The `acq` subcommands. Each takes the arguments after its name and returns an exit code;
// user errors are thrown as UserError and reported by main.
#pragma once

#include <string>
#include <vector>

namespace acq::cli {

using Argv = std::vector<std::string>;

int BasisBuild(const Argv& args);
int BasisEval(const Argv& args);
int BasisInfo(const Argv& args);
int MaterialConvert(const Argv& args);
int DirectionsRandom(const Argv& args);
int DirectionsOptimize(const Argv& args);
int DirectionsEval(const Argv& args);
int DirectionsPlan(const Argv& args);
int ReconstructSynthetic(const Argv& args);
int RenderQuicklook(const Argv& args);
int RenderView(const Argv& args);
int ExportPbr(const Argv& args);
int ExportMitsuba(const Argv& args);
int RenderSpheres(const Argv& args);
int RenderExport(const Argv& args);
int CalibrateDetect(const Argv& args);
int CalibrateIntrinsics(const Argv& args);
int CalibrateExtrinsics(const Argv& args);
int CalibrateCorrespondence(const Argv& args);
int CalibrateSynthesize(const Argv& args);
int SessionRepair(const Argv& args);
int SessionProcess(const Argv& args);

}  // namespace acq::cli
