// acqd: runs a capture session from a plan (issue 8): argument parsing and wiring only.
//
// The plan is loaded and validated completely before anything is opened or moved (every error
// with file:line:column and the fix; session/dry_run.h checks the files the run will read);
// `--dry-run` prints the schedule. A run opens the control socket, the backend (for sim:
// re-executed into the simulated instrument's environment, sim/environment.h) and hands the
// session to the session library (session/run.h), which verifies the catalog, opens the devices
// through the opener here, captures, processes and reports; a simulated session is scored
// against its ground truth (session/truth_score.h).
#include <cstdio>
#include <memory>
#include <string>

#include "acq/plan.h"
#include "core/error.h"
#include "core/stop_request.h"
#include "daemon/control.h"
#include "daemon/parse_args.h"
#include "hw/aravis_camera.h"
#include "hw/protocol_gantry.h"
#include "hw/usb_transport.h"
#include "session/dry_run.h"
#include "session/preview.h"
#include "session/run.h"
#include "session/sim_instrument.h"
#include "session/truth_score.h"
#include "sim/environment.h"
#include "sim/instrument.h"

namespace acq {
namespace {

// The gantry behind a USB transport: the transport lives as long as the gantry that talks
// through it.
class UsbGantry : public ProtocolGantry {
 public:
  explicit UsbGantry(std::unique_ptr<UsbTransport> transport)
      : ProtocolGantry(*transport), transport_(std::move(transport)) {}

 private:
  std::unique_ptr<UsbTransport> transport_;
};

// The instrument's devices through their real drivers: the gantry on USB, the camera on GigE
// Vision (the simulated instrument's, where `instrument` is given).
SessionDevices OpenInstrument(const Plan& plan, sim::Instrument* instrument,
                              const std::function<void(const std::string&)>& phase) {
  UsbDeviceId usb = plan.gantry.usb;
  AravisCameraOptions camera;
  camera.id = plan.camera.id;
  if (instrument) {
    usb.serial = instrument->usb().serial;
    camera.id = instrument->camera_address();
  }
  SessionDevices d;
  phase("opening the gantry (" + usb.Describe() + ")");
  d.gantry = std::make_unique<UsbGantry>(std::make_unique<UsbTransport>(usb));
  phase("opening the camera (" + camera.id + ")");
  d.camera = std::make_unique<AravisCamera>(camera);
  d.gantry_id = usb.Describe();
  if (instrument) {
    instrument->WriteGroundTruth(plan.output + "/ground_truth");
    d.ask_operator = plan.sim.operator_prompts;
    d.place = [instrument](const Placement& p) { instrument->Place(p); };
    d.light_intensity =
        instrument->LightIntensityInCounts(MaxValue(plan.camera.settings.pixel_format));
  }
  return d;
}

// The preview: the camera alone (the simulated one with the sample under it), no session.
int Preview(const Plan& plan, sim::Instrument* instrument, ControlServer& control,
            SessionStatus& status) {
  if (plan.backend == Backend::kReplay)
    throw UserError("--preview", "a replay has no camera to preview", "give a sim or usb plan");
  AravisCameraOptions options;
  options.id = instrument ? instrument->camera_address() : plan.camera.id;
  status.step = "opening the camera (" + options.id + ") for a preview";
  control.Publish(status);
  std::printf("%s\n", status.step.c_str());
  AravisCamera camera(options);
  if (instrument) instrument->Place(Placement{Item::kSample, 0});
  std::printf("preview: streaming to the live view (acqctl serve); abort or Ctrl-C ends it\n");
  std::fflush(stdout);
  RunPreview(plan, camera, control, status);
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app{"acqd: runs a capture session from a plan (docs/session-and-plan.md)", "acqd"};
  std::string session, socket = DefaultControlSocket();
  bool dry_run = false, preview = false;
  app.add_option("--session", session, "the plan (.yaml) of the session to run (required)")
      ->option_text("PLAN.yaml");
  app.add_flag("--dry-run", dry_run,
               "validate the plan, print the schedule, the visiting order and the estimated "
               "time; open no device, move nothing");
  app.add_flag("--preview", preview,
               "open the camera only and stream its frames to the live view (acqctl serve) at "
               "a few frames a second, the exposure set from the page; nothing moves, nothing is "
               "recorded; abort or Ctrl-C ends it");
  app.add_option("--socket", socket, "the control socket acqctl talks to")
      ->option_text("PATH (default $XDG_RUNTIME_DIR/acqd.sock)");
  if (const std::optional<int> exit = ParseArgs(app, argc, argv)) return *exit;
  if (session.empty()) {
    std::fputs(("acqd: --session PLAN.yaml is required\n" + app.help()).c_str(), stderr);
    return 1;
  }

  const Plan plan = LoadPlan(session);
  CheckSessionInputs(plan);
  // The simulated sample's files (a label or weight image, a height map) read and checked
  // before the dry run answers and before anything moves.
  if (plan.backend == Backend::kSim) InstrumentOptionsOf(plan).Check();
  if (dry_run) {
    std::fputs(DryRunText(plan).c_str(), stdout);
    return 0;
  }
  // The simulated instrument lives in this process, in its own network namespace, under
  // umockdev: re-execute into that environment first.
  if (plan.backend == Backend::kSim && !sim::EnvironmentReady())
    throw UserError("acqd", sim::ReexecIntoEnvironment(argc, argv),
                    "the sim backend needs unshare (util-linux), ip (iproute2) and umockdev");
  InstallStopHandlers();
  // The control socket first, so that `acqctl status` shows every phase of the start.
  ControlServer control(socket);
  SessionStatus status;
  std::unique_ptr<sim::Instrument> instrument;
  if (plan.backend == Backend::kSim) {
    status.step = "building the simulated instrument";
    control.Publish(status);
    std::printf("%s\n", status.step.c_str());
    instrument = std::make_unique<sim::Instrument>(InstrumentOptionsOf(plan));
  }
  if (preview) return Preview(plan, instrument.get(), control, status);
  SessionHooks hooks;
  hooks.open = [&](const std::function<void(const std::string&)>& phase) {
    if (plan.backend == Backend::kReplay) {
      phase("opening the recorded session " + plan.replay_session);
      return OpenReplayDevices(plan);
    }
    return OpenInstrument(plan, instrument.get(), phase);
  };
  if (instrument)
    hooks.score = [&](SessionReport* report) {
      ScoreAgainstGroundTruth(plan, plan.output, report);
    };
  RunSession(plan, control, status, hooks);
  return 0;
}

}  // namespace
}  // namespace acq

int main(int argc, char** argv) {
  try {
    return acq::Run(argc, argv);
  } catch (const acq::Stopped& e) {
    std::fprintf(stderr, "acqd: %s\n", e.what());
    return 128 + e.signal_number();    // the shell's convention for "ended by this signal"
  } catch (const std::exception& e) {  // ours (UserError) or a library's: a message, no crash
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
