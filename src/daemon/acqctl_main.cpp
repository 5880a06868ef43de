// acqctl: talks to a running acqd over its control socket (issue 8).
//   acqctl [--socket PATH] status [--json] | watch | pause | resume | abort | confirm
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "core/error.h"
#include "daemon/control.h"

namespace {

constexpr const char* kUsage =
    "usage: acqctl [--socket PATH] status [--json] | watch | pause | resume | abort | confirm\n";

// A field of the status line (flat JSON written by acqd), as text; "" when absent.
std::string Field(const std::string& json, const std::string& name) {
  const std::string key = "\"" + name + "\": ";
  const std::size_t at = json.find(key);
  if (at == std::string::npos) return {};
  std::size_t begin = at + key.size(), end;
  if (json[begin] == '"') {
    end = begin + 1;
    while (end < json.size() && (json[end] != '"' || json[end - 1] == '\\')) ++end;
    return json.substr(begin + 1, end - begin - 1);
  }
  if (json[begin] == '[') return json.substr(begin, json.find(']', begin) - begin + 1);
  end = json.find_first_of(",}", begin);
  return json.substr(begin, end - begin);
}

void PrintStatus(const std::string& json) {
  std::printf("state      %s\n", Field(json, "state").c_str());
  std::printf("step       %s\n", Field(json, "step").c_str());
  std::printf("progress   %.1f%%, about %s s left\n", 100 * std::stod(Field(json, "progress")),
              Field(json, "eta_s").c_str());
  std::printf("arms       %s deg (light theta, phi, camera theta, phi)\n",
              Field(json, "arms_deg").c_str());
  std::printf("frames     %s (%s incomplete, retaken); gantry retransmissions %s\n",
              Field(json, "frames").c_str(), Field(json, "incomplete_frames").c_str(),
              Field(json, "retransmissions").c_str());
  if (!Field(json, "prompt").empty())
    std::printf("waiting    %s  (then: acqctl confirm)\n", Field(json, "prompt").c_str());
  if (!Field(json, "last_error").empty())
    std::printf("last error %s\n", Field(json, "last_error").c_str());
}

int Run(int argc, char** argv) {
  std::string socket = acq::DefaultControlSocket(), command;
  bool json = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--socket") && i + 1 < argc)
      socket = argv[++i];
    else if (!std::strcmp(argv[i], "--json"))
      json = true;
    else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (command.empty())
      command = argv[i];
    else {
      std::fprintf(stderr, "acqctl: unexpected '%s'\n%s", argv[i], kUsage);
      return 1;
    }
  }
  if (command == "status") {
    const std::string reply = acq::ControlRequest(socket, "status");
    if (json)
      std::printf("%s\n", reply.c_str());
    else
      PrintStatus(reply);
    return 0;
  }
  if (command == "watch") {
    for (;;) {
      const std::string reply = acq::ControlRequest(socket, "status");
      const double p = std::stod(Field(reply, "progress"));
      const int filled = int(p * 40);
      std::printf("\r[%s%s] %5.1f%% %-10s %-40.40s", std::string(std::size_t(filled), '#').c_str(),
                  std::string(std::size_t(40 - filled), ' ').c_str(), 100 * p,
                  Field(reply, "state").c_str(), Field(reply, "step").c_str());
      std::fflush(stdout);
      const std::string state = Field(reply, "state");
      if (state == "done" || state == "failed") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    std::printf("\n");
    return 0;
  }
  if (command == "pause" || command == "resume" || command == "abort" || command == "confirm") {
    const std::string reply = acq::ControlRequest(socket, command);
    std::printf("%s\n", reply.c_str());
    return reply.rfind("ok", 0) == 0 ? 0 : 1;
  }
  std::fputs(kUsage, stderr);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const acq::UserError& e) {
    std::fprintf(stderr, "acqctl: %s\n", e.what());
    return 1;
  }
}
