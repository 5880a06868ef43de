// acqd's control channel and acqctl, the real binary, against a server whose sequencer is stuck.
#include <catch2/catch.hpp>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"
#include "daemon/control.h"

using namespace acq;

namespace {

struct Output {
  int rc;
  std::string text;
};

Output Acqctl(const std::string& socket, const std::string& args) {
  const std::string command =
      std::string(ACQCTL_PATH) + " --socket " + socket + " " + args + " 2>&1";
  FILE* p = popen(command.c_str(), "r");
  REQUIRE(p);
  std::string out;
  char line[512];
  while (fgets(line, sizeof line, p)) out += line;
  const int status = pclose(p);
  return {WEXITSTATUS(status), out};
}

std::string SocketPath(const char* name) {
  return "/tmp/acq-test-" + std::to_string(getpid()) + "-" + name + ".sock";
}

}  // namespace

TEST_CASE("control: acqctl status answers within 100 ms while the sequencer is stuck",
          "[control]") {
  const std::string path = SocketPath("status");
  ControlServer server(path);
  struct stat st;
  REQUIRE(stat(path.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0600);  // owner only

  SessionStatus s;
  s.state = "running";
  s.step = "sample pose 7 of 20, exposure 2 of 3";
  s.progress = 0.35;
  s.eta_s = 412;
  s.arms_deg[2] = 41.5;
  s.frames = 57;
  s.last_error = "camera: lost (timed out) \"retaken\"";
  server.Publish(s);
  // The sequencer now holds its own lock for 3 s (stuck in a move, say); the server never
  // takes that lock, only the snapshot's.
  std::mutex sequencer;
  std::thread stuck([&] {
    std::lock_guard<std::mutex> hold(sequencer);
    std::this_thread::sleep_for(std::chrono::seconds(3));
  });
  std::vector<double> ms;
  Output last;
  for (int i = 0; i < 20; ++i) {
    const auto t = std::chrono::steady_clock::now();
    last = Acqctl(path, "status --json");
    ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count());
  }
  stuck.join();
  std::sort(ms.begin(), ms.end());
  WARN("acqctl status (process start included): median " << ms[10] << " ms, worst " << ms[19]
                                                         << " ms");
  CHECK(last.rc == 0);
  CHECK(last.text.find("\"state\": \"running\"") != std::string::npos);
  CHECK(last.text.find("\"step\": \"sample pose 7 of 20, exposure 2 of 3\"") != std::string::npos);
  CHECK(last.text.find("\\\"retaken\\\"") != std::string::npos);  // quotes escaped in JSON
  CHECK(ms[19] < 100);
  const Output human = Acqctl(path, "status");
  CHECK(human.text.find("progress   35.0%, about 412.0 s left") != std::string::npos);
  CHECK(human.text.find("frames     57") != std::string::npos);
}

TEST_CASE(
    "control: commands are queued for the sequencer; a second daemon is refused; a "
    "stale socket is replaced; no daemon is a clear error",
    "[control]") {
  const std::string path = SocketPath("commands");
  {
    ControlServer server(path);
    CHECK(Acqctl(path, "pause").rc == 0);
    CHECK(Acqctl(path, "confirm").rc == 0);
    CHECK(server.TakeCommand() == "pause");
    CHECK(server.TakeCommand() == "confirm");
    CHECK(server.TakeCommand() == "");
    CHECK_THROWS_WITH(ControlServer(path), Catch::Contains("another acqd is running"));
    CHECK(ControlRequest(path, "jump").find("error unknown request 'jump'") == 0);
  }
  // A socket file left by a killed acqd (bound, never answered).
  {
    const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::snprintf(a.sun_path, sizeof a.sun_path, "%s", path.c_str());
    REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    close(fd);
  }
  {
    ControlServer replaced(path);
    CHECK(Acqctl(path, "status --json").rc == 0);
  }
  const Output none = Acqctl(path, "status");
  CHECK(none.rc == 1);
  CHECK(none.text.find("no acqd answers here") != std::string::npos);
  CHECK(none.text.find("is acqd running?") != std::string::npos);
}
