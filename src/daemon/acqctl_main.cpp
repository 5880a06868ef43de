// acqctl: talks to a running acqd over its control socket (issue 8).
//   acqctl [--socket PATH] status [--json] | watch | pause | resume | abort | confirm [PROMPT_ID]
//          | serve [--port 8080] [--bind 127.0.0.1]  (the live view in a browser, live_view.h)
// A reply that is not what acqd sends (not JSON, a field missing or of the wrong type) is an
// error message and exit 1, never a crash (issue 22).
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "daemon/control.h"
#include "daemon/live_view.h"
#include "daemon/parse_args.h"

namespace {

using nlohmann::json;

// The status line parsed, checked for the fields acqctl reads.
json ParseStatus(const std::string& socket, const std::string& reply) {
  const json j = json::parse(reply, nullptr, false);
  auto bad = [&](const std::string& why) {
    return acq::UserError(socket,
                          "acqd's status reply is malformed (" + why + "): " + reply.substr(0, 200),
                          "is the socket really acqd's? acqd and acqctl from one build?");
  };
  if (j.is_discarded() || !j.is_object()) throw bad("not a JSON object");
  for (const char* text : {"state", "step", "prompt", "last_error"})
    if (!j.contains(text) || !j[text].is_string()) throw bad(std::string("no text '") + text + "'");
  for (const char* number :
       {"progress", "frames", "incomplete_frames", "retransmissions", "prompt_id"})
    if (!j.contains(number) || !j[number].is_number())
      throw bad(std::string("no number '") + number + "'");
  return j;
}

std::string Number(const json& j, const char* key, const char* format) {
  if (!j.contains(key) || !j[key].is_number()) return "unknown";
  char text[64];
  std::snprintf(text, sizeof text, format, j[key].get<double>());
  return text;
}

void PrintStatus(const json& j) {
  std::printf("state      %s\n", j["state"].get<std::string>().c_str());
  std::printf("step       %s\n", j["step"].get<std::string>().c_str());
  std::printf("progress   %.1f%%, about %s s left\n", 100 * j["progress"].get<double>(),
              Number(j, "eta_s", "%.1f").c_str());
  std::string arms;
  if (j.contains("arms_deg") && j["arms_deg"].is_array())
    for (const json& a : j["arms_deg"])
      arms += (arms.empty() ? "" : ", ") + (a.is_number() ? std::to_string(a.get<double>()) : "?");
  std::printf("arms       [%s] deg (light theta, phi, camera theta, phi)\n", arms.c_str());
  std::printf("frames     %s (%s incomplete, retaken); gantry retransmissions %s\n",
              Number(j, "frames", "%.0f").c_str(), Number(j, "incomplete_frames", "%.0f").c_str(),
              Number(j, "retransmissions", "%.0f").c_str());
  const std::string prompt = j["prompt"];
  if (!prompt.empty())
    std::printf("waiting    prompt %s: %s  (then: acqctl confirm)\n",
                Number(j, "prompt_id", "%.0f").c_str(), prompt.c_str());
  const std::string error = j["last_error"];
  if (!error.empty()) std::printf("last error %s\n", error.c_str());
}

int Watch(const std::string& socket) {
  for (;;) {
    const json j = ParseStatus(socket, acq::ControlRequest(socket, "status"));
    const double p = std::clamp(j["progress"].get<double>(), 0.0, 1.0);
    const int filled = int(p * 40);
    std::printf("\r[%s%s] %5.1f%% %-10s %-40.40s", std::string(std::size_t(filled), '#').c_str(),
                std::string(std::size_t(40 - filled), ' ').c_str(), 100 * p,
                j["state"].get<std::string>().c_str(), j["step"].get<std::string>().c_str());
    std::fflush(stdout);
    const auto state = acq::ParseDaemonState(j["state"]);
    if (state && acq::IsFinal(*state)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  std::printf("\n");
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app{"acqctl: talks to a running acqd over its control socket", "acqctl"};
  std::string socket = acq::DefaultControlSocket();
  app.add_option("--socket", socket, "acqd's control socket")
      ->option_text("PATH (default $XDG_RUNTIME_DIR/acqd.sock)");
  app.require_subcommand(0, 1);
  app.fallthrough();  // --socket also after the command, as before
  bool json_out = false;
  CLI::App* status = app.add_subcommand(
      "status", "the session's state, step, progress, arms, frames, prompt, last error");
  status->add_flag("--json", json_out, "the status line as acqd sends it (JSON)");
  CLI::App* watch = app.add_subcommand("watch", "a progress bar until the session ends");
  app.add_subcommand("pause", "at the sequencer's next safe point (between frames)");
  app.add_subcommand("resume", "go on after a pause");
  app.add_subcommand("abort", "stop the gantry and end the session, resumable");
  std::string prompt_id;
  app.add_subcommand("confirm", "answer the operator prompt showing")
      ->add_option("PROMPT_ID", prompt_id, "the prompt's id (acqctl status)");
  acq::LiveViewOptions view;
  CLI::App* serve =
      app.add_subcommand("serve", "the live view: a web page of the session (docs/live-view.md)");
  serve->add_option("--port", view.port, "TCP port (0: any free one)")->default_val(view.port);
  serve->add_option("--bind", view.bind, "address to listen on; beyond 127.0.0.1 is warned of")
      ->default_val(view.bind);
  serve->add_option("--session", view.session,
                    "a session folder to show (a finished one) until acqd reports its own");
  if (const std::optional<int> exit = acq::ParseArgs(app, argc, argv)) return *exit;
  if (app.get_subcommands().empty()) {
    std::fputs(("acqctl: a command is required\n" + app.help()).c_str(), stderr);
    return 1;
  }
  const CLI::App* command = app.get_subcommands().front();
  if (command == status) {
    const std::string reply = acq::ControlRequest(socket, "status");
    const json j = ParseStatus(socket, reply);
    if (json_out)
      std::printf("%s\n", reply.c_str());
    else
      PrintStatus(j);
    return 0;
  }
  if (command == watch) return Watch(socket);
  if (command == serve) {
    view.socket = socket;
    return acq::ServeLiveView(view);
  }
  const std::string name = command->get_name();
  const std::string request = prompt_id.empty() ? name : name + " " + prompt_id;
  const std::string reply = acq::ControlRequest(socket, request);
  std::printf("%s\n", reply.c_str());
  return reply.rfind("ok", 0) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  ::signal(SIGPIPE, SIG_IGN);  // a vanished acqd is an error on the write, not our death
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "acqctl: %s\n", e.what());
    return 1;
  }
}
