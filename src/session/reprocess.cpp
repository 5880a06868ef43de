#include "session/reprocess.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <yaml-cpp/yaml.h>

#include "acq/plan_record.h"
#include "core/error.h"
#include "io/session_catalog.h"
#include "io/session_lock.h"
#include "session/session_calibration.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

constexpr ProcessStage kStages[] = {ProcessStage::kHdr, ProcessStage::kCalibration,
                                    ProcessStage::kReconstruction};

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The folder the session's plan copy is relative to (plan_record.h), or the session itself for
// a session recorded before the folder was.
std::string PlanFolder(const std::string& session) {
  std::string folder = ReadText(fs::path(session) / kPlanFolderFile);
  while (!folder.empty() && (folder.back() == '\n' || folder.back() == '\r')) folder.pop_back();
  return folder.empty() ? session : folder;
}

// The session's plan with `settings` ("a.b=value", value in YAML) applied and the output set,
// as YAML text.
std::string PlanWithSettings(const std::string& plan_path, const std::vector<std::string>& settings,
                             const std::string& output) {
  YAML::Node root = YAML::LoadFile(plan_path);
  for (const std::string& setting : settings) {
    const std::size_t eq = setting.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == setting.size())
      throw UserError("--set " + setting, "expected KEY=VALUE",
                      "e.g. --set reconstruction.k=10 or --set reconstruction.lookup=interpolated");
    std::vector<std::string> keys;
    std::istringstream path(setting.substr(0, eq));
    for (std::string key; std::getline(path, key, '.');) keys.push_back(key);
    YAML::Node node = root;
    for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
      YAML::Node child = node[keys[i]];
      node.reset(child);
    }
    try {
      node[keys.back()] = YAML::Load(setting.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw UserError("--set " + setting, "the value is not YAML: " + e.msg,
                      "quote a text value, write a list as [a, b]");
    }
  }
  root["output"] = fs::absolute(output).lexically_normal().string();
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

void LinkOrCopy(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_hard_link(from, to, ec);  // the frames are read-only to processing: share them
  if (ec) fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

// The session copied to `to` for processing there: frames linked, the catalog copied
// consistently, the record of the plan, and the outputs of the stages before `from`.
void CopySession(const std::string& from_dir, const SessionCatalog& catalog, const std::string& to,
                 ProcessStage from) {
  const fs::path src(from_dir), dst(to);
  fs::create_directories(dst / "frames");
  for (const fs::directory_entry& e : fs::directory_iterator(src / "frames"))
    if (e.is_regular_file() && IsFrameFileName(e.path().filename().string()))
      LinkOrCopy(e.path(), dst / "frames" / e.path().filename());
  catalog.CopyTo(to);
  std::vector<std::string> copied = PlanRecordFiles();
  // The correspondence maps record their inputs (view_correspondence.h): copied, each is reused
  // where the calibration comes out as it was and computed again where it does not.
  copied.insert(copied.end(), {"directions.tsv", "ground_truth", "correspondence"});
  if (from > ProcessStage::kHdr) copied.push_back("hdr");
  if (from > ProcessStage::kCalibration) copied.push_back("calibration");
  for (const std::string& name : copied)
    if (fs::exists(src / name))
      fs::copy(src / name, dst / name,
               fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

}  // namespace

const char* ToString(ProcessStage stage) {
  switch (stage) {
    case ProcessStage::kHdr:
      return "hdr";
    case ProcessStage::kCalibration:
      return "calibration";
    case ProcessStage::kReconstruction:
      return "reconstruction";
  }
  return "?";
}

std::optional<ProcessStage> ParseProcessStage(const std::string& text) {
  for (ProcessStage s : kStages)
    if (text == ToString(s)) return s;
  return std::nullopt;
}

void ReprocessOptions::Check() const {
  const fs::path dir(session);
  if (!fs::is_regular_file(dir / "catalog.sqlite") || !fs::is_regular_file(dir / "plan.yaml"))
    throw UserError(session, "not a captured session (no catalog.sqlite and plan.yaml)",
                    "give the output folder of an acqd session");
  if (output.empty()) return;
  std::error_code ec;
  if (fs::exists(output) && !fs::is_empty(output, ec))
    throw UserError("-o " + output, "the folder exists and is not empty",
                    "give a new folder for the processed copy");
  const fs::path in = fs::weakly_canonical(dir), out = fs::weakly_canonical(output);
  if (out == in || out.string().rfind(in.string() + "/", 0) == 0)
    throw UserError("-o " + output, "the copy would lie inside the session it copies",
                    "give a folder outside " + session);
}

namespace {

// Where a refusal of the scratch plan lies for the user: the --set that names the refused key
// (the captured plan was checked when it was captured, so a refusal comes from a setting).
std::string SettingRefused(const UserError& e, const std::vector<std::string>& settings) {
  for (const std::string& s : settings) {
    const std::string key = s.substr(0, s.find('='));
    if (!key.empty() && e.problem().find(key) != std::string::npos)
      return "acq session process --set " + s;
  }
  return "acq session process --set";
}

// The plan as it will be processed, loaded (and so checked) from a scratch copy before any file
// is written: a refused setting leaves no half-made output behind.
Plan CheckedPlan(const std::string& text, const std::string& folder,
                 const std::vector<std::string>& settings) {
  const fs::path scratch =
      fs::temp_directory_path() / ("acq-session-process-" + std::to_string(getpid()));
  fs::create_directories(scratch);
  const std::string path = (scratch / "processed_plan.yaml").string();
  std::ofstream(path) << text;
  try {
    Plan plan = LoadPlan(path, folder);
    fs::remove_all(scratch);
    return plan;
  } catch (const UserError& e) {
    fs::remove_all(scratch);
    // The scratch file is gone and was never the user's: name the setting instead.
    if (e.where().rfind(path, 0) != 0) throw;
    throw UserError(SettingRefused(e, settings), e.problem(), e.fix());
  } catch (...) {
    fs::remove_all(scratch);
    throw;
  }
}

}  // namespace

ReprocessResult ReprocessSession(const ReprocessOptions& options) {
  options.Check();
  const SessionLock source_lock(options.session, "acq session process");
  const std::string target = options.output.empty() ? options.session : options.output;
  const std::string folder = PlanFolder(options.session);
  const std::string text =
      PlanWithSettings(options.session + "/plan.yaml", options.settings, target);
  // What was captured cannot change after the fact: refused before anything is written.
  const std::vector<std::string> capture =
      CaptureDifferences(CheckedPlan(text, folder, options.settings), options.session);
  if (!capture.empty()) {
    std::string listed;
    for (const std::string& c : capture) listed += (listed.empty() ? "" : "; ") + c;
    throw UserError("acq session process --set",
                    "these settings change what was captured: " + listed,
                    "acq session process changes processing settings only (reconstruction.*, "
                    "calibration.lensmodel); capture a new session for the others");
  }

  std::optional<SessionLock> target_lock;
  if (!options.output.empty()) {
    const SessionCatalog source(options.session);
    CopySession(options.session, source, target, options.from);
    target_lock.emplace(target, "acq session process");
  }
  // The plan as processed, kept beside the outputs it made.
  const std::string processed = target + "/processed_plan.yaml";
  std::ofstream(processed) << text;
  ReprocessResult result{LoadPlan(processed, folder), {}, {}};
  SessionCatalog catalog(target);
  result.processing_changes = RecordOrCheckPlan(result.plan, target, catalog).processing_changes;
  if (options.from == ProcessStage::kHdr) fs::remove_all(fs::path(target) / "hdr");
  PrecomputedStages precomputed;
  if (options.from == ProcessStage::kReconstruction)
    precomputed.calibration = ReadSessionCalibration(target);
  SessionGeometry geometry;
  if (!result.plan.spectralon) {
    const std::string light = catalog.Decision(kLightIntensityDecision);
    if (light.empty())
      throw UserError(target, "no Spectralon captures and no light intensity recorded",
                      "process this session with acqd, which knows its light");
    geometry.light_intensity = std::stod(light);
  }
  catalog.Event("info", std::string("acq session process from ") + ToString(options.from) +
                            (options.output.empty() ? "" : " (a copy of " + options.session + ")"));
  result.process = ProcessSession(result.plan, catalog, geometry, std::move(precomputed));
  return result;
}

}  // namespace acq
