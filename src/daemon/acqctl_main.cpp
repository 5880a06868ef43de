// acqctl: talks to a running acqd over its control socket (issue 8).
//   acqctl [--socket PATH] status [--json] | watch | pause | resume | abort | confirm [PROMPT_ID]
// A reply that is not what acqd sends (not JSON, a field missing or of the wrong type) is an
// error message and exit 1, never a crash (issue 22).
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "daemon/control.h"

namespace {

using nlohmann::json;

constexpr const char* kUsage =
    "usage: acqctl [--socket PATH] COMMAND\n"
    "  status [--json]     the session's state, step, progress, arms, frames, prompt, last error\n"
    "  watch               a progress bar until the session ends\n"
    "  pause | resume      at the sequencer's next safe point (between frames)\n"
    "  abort               stop the gantry and end the session, resumable\n"
    "  confirm [PROMPT_ID] answer the operator prompt showing (its id: acqctl status)\n"
    "  --socket PATH       acqd's control socket (default $XDG_RUNTIME_DIR/acqd.sock)\n";

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
  std::string socket = acq::DefaultControlSocket(), command, argument;
  bool json_out = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--socket") && i + 1 < argc)
      socket = argv[++i];
    else if (!std::strcmp(argv[i], "--json"))
      json_out = true;
    else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (command.empty())
      command = argv[i];
    else if (command == "confirm" && argument.empty())
      argument = argv[i];
    else {
      std::fprintf(stderr, "acqctl: unexpected '%s'\n%s", argv[i], kUsage);
      return 1;
    }
  }
  if (command == "status") {
    const std::string reply = acq::ControlRequest(socket, "status");
    const json j = ParseStatus(socket, reply);
    if (json_out)
      std::printf("%s\n", reply.c_str());
    else
      PrintStatus(j);
    return 0;
  }
  if (command == "watch") return Watch(socket);
  if (acq::ParseCommandKind(command)) {
    const std::string request = argument.empty() ? command : command + " " + argument;
    const std::string reply = acq::ControlRequest(socket, request);
    std::printf("%s\n", reply.c_str());
    return reply.rfind("ok", 0) == 0 ? 0 : 1;
  }
  std::fprintf(stderr, "acqctl: unknown command '%s'\n%s", command.c_str(), kUsage);
  return 1;
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
