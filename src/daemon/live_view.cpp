#include "daemon/live_view.h"

#include <signal.h>

#include <httplib.h>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "daemon/control.h"
#include "embedded_live_view.h"

namespace acq {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// 128 bits from the kernel's random source, as hex.
std::string RandomToken() {
  std::random_device device;  // /dev/urandom on Linux
  std::string token;
  char hex[9];
  for (int i = 0; i < 4; ++i) {
    std::snprintf(hex, sizeof hex, "%08x", unsigned(device()));
    token += hex;
  }
  return token;
}

// Equal texts in time independent of where they differ.
bool SameToken(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

void Json(httplib::Response& res, const json& j) {
  res.set_content(j.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

// acqd's reply to `request`, or the reason there is none (acqd not running, the socket not
// acqd's) as {"state": "unreachable", "error": ...}: the page shows it and retries.
json AskAcqd(const std::string& socket, const std::string& request) {
  try {
    const std::string reply = ControlRequest(socket, request, 1000);
    json j = json::parse(reply, nullptr, false);
    if (j.is_discarded() || !j.is_object())
      return {{"state", "unreachable"}, {"error", "not acqd's reply: " + reply.substr(0, 120)}};
    return j;
  } catch (const std::exception& e) {
    return {{"state", "unreachable"}, {"error", e.what()}};
  }
}

// The session folder being watched: the one acqd reports, and after acqd has ended the last
// one it reported (or --session's), so that a finished session's results stay on the page.
class WatchedSession {
 public:
  explicit WatchedSession(std::string socket, std::string folder)
      : socket_(std::move(socket)), folder_(std::move(folder)) {}
  // Asks acqd at most every kRecheck (a session's folder does not change while it runs; a file
  // fetch should not cost a control request).
  std::string Folder() {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (asked_ && now - *asked_ < kRecheck) return folder_;
    asked_ = now;
    const json s = AskAcqd(socket_, "status");
    if (s.contains("session") && s["session"].is_string() &&
        !s["session"].get<std::string>().empty())
      folder_ = s["session"].get<std::string>();
    return folder_;
  }

 private:
  static constexpr std::chrono::seconds kRecheck{5};
  const std::string socket_;
  std::mutex mutex_;  // the server answers on several threads
  std::string folder_;
  std::optional<std::chrono::steady_clock::time_point> asked_;
};

// One file name of a session folder the page may show: letters, digits, _ - . only, not
// leading with a dot, ending in `extension`.
bool PlainName(const std::string& name, const std::string& extension) {
  if (name.empty() || name.size() > 128 || name[0] == '.') return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      return false;
  return fs::path(name).extension() == extension;
}

// The folders of a session whose PNGs the page shows: the poses' thumbnails and the renders.
constexpr const char* kImageFolders[] = {"hdr", "renders"};

// A file the page may show: report.txt, report.json, or a PNG in one of kImageFolders (one
// name, no folders below, nothing leading elsewhere).
bool Servable(const std::string& path) {
  if (path == "report.txt" || path == "report.json") return true;
  for (const std::string folder : kImageFolders)
    if (path.rfind(folder + "/", 0) == 0) return PlainName(path.substr(folder.size() + 1), ".png");
  return false;
}

// The PNG names in `folder`, oldest first (the poses in the order they were merged; ties by
// name).
json PngsIn(const fs::path& folder) {
  std::vector<std::pair<fs::file_time_type, std::string>> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (PlainName(e.path().filename().string(), ".png"))
      found.emplace_back(e.last_write_time(ec), e.path().filename().string());
  std::sort(found.begin(), found.end());
  json names = json::array();
  for (const auto& f : found) names.push_back(f.second);
  return names;
}

void Routes(httplib::Server& server, const LiveViewOptions& o) {
  server.set_pre_routing_handler(
      [token = o.token](const httplib::Request& req, httplib::Response& res) {
        const std::string given = req.has_param("token") ? req.get_param_value("token")
                                                         : req.get_header_value("X-Acq-Token");
        if (SameToken(given, token)) return httplib::Server::HandlerResponse::Unhandled;
        res.status = 403;
        res.set_content("403: the live view needs its access token (printed by acqctl serve)\n",
                        "text/plain");
        return httplib::Server::HandlerResponse::Handled;
      });
  server.Get("/", [](const httplib::Request&, httplib::Response& res) {
    res.set_content(embedded::kLiveViewPage, "text/html; charset=utf-8");
  });
  const std::string socket = o.socket;
  server.Get("/api/status", [socket](const httplib::Request&, httplib::Response& res) {
    Json(res, AskAcqd(socket, "status"));
  });
  server.Get("/api/frame", [socket](const httplib::Request&, httplib::Response& res) {
    Json(res, AskAcqd(socket, "frame"));
  });
  server.Post("/api/command", [socket](const httplib::Request& req, httplib::Response& res) {
    const std::string name = req.get_param_value("name");
    // The argument goes into acqd's request line: a number or nothing, never another line.
    const std::string argument = name == "confirm"
                                     ? req.get_param_value("prompt")
                                     : (name == "exposure" ? req.get_param_value("value") : "");
    const bool known = name == "confirm" || name == "abort" || name == "pause" ||
                       name == "resume" || name == "exposure";
    if (!known || argument.find_first_not_of("0123456789.") != std::string::npos ||
        argument.size() > 16) {
      res.status = 400;
      return Json(res,
                  {{"ok", false}, {"reply", "not a command of the live view: '" + name + "'"}});
    }
    const std::string request = argument.empty() ? name : name + " " + argument;
    try {
      const std::string reply = ControlRequest(socket, request, 1000);
      Json(res, {{"ok", reply.rfind("ok", 0) == 0}, {"reply", reply}});
    } catch (const std::exception& e) {
      Json(res, {{"ok", false}, {"reply", e.what()}});
    }
  });
  auto watched = std::make_shared<WatchedSession>(socket, o.session);
  server.Get("/api/files", [watched](const httplib::Request&, httplib::Response& res) {
    const std::string folder = watched->Folder();
    json out = {{"session", folder}, {"report", false}};
    for (const std::string sub : kImageFolders)
      out[sub] = folder.empty() ? json::array() : PngsIn(fs::path(folder) / sub);
    out["report"] = !folder.empty() && fs::is_regular_file(fs::path(folder) / "report.txt");
    Json(res, out);
  });
  server.Get("/api/file", [watched](const httplib::Request& req, httplib::Response& res) {
    const std::string path = req.get_param_value("path");
    const std::string folder = watched->Folder();
    std::ifstream in;
    if (Servable(path) && !folder.empty()) in.open(fs::path(folder) / path, std::ios::binary);
    if (!in) {
      res.status = 404;
      return res.set_content("404: no such file of the session\n", "text/plain");
    }
    std::stringstream s;
    s << in.rdbuf();
    res.set_content(s.str(), fs::path(path).extension() == ".png"    ? "image/png"
                             : fs::path(path).extension() == ".json" ? "application/json"
                                                                     : "text/plain; charset=utf-8");
  });
}

}  // namespace

void LiveViewOptions::Check() const {
  if (port < 0 || port > 65535)
    throw UserError("--port", "must be between 0 and 65535, got " + std::to_string(port),
                    "the default is 8080; 0 picks a free port");
  if (bind.empty()) throw UserError("--bind", "is empty", "give an address, e.g. 127.0.0.1");
  if (!session.empty() && !fs::is_directory(session))
    throw UserError("--session " + session, "is not a folder",
                    "give a session folder (the plan's output), e.g. out/sessions/sim-card");
}

int ServeLiveView(LiveViewOptions o) {
  o.Check();
  if (o.token.empty()) o.token = RandomToken();
  httplib::Server server;
  // SO_REUSEADDR only: cpp-httplib's default adds SO_REUSEPORT, which lets a second server
  // share a port already served (and split the requests between the two).
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  Routes(server, o);
  int port = o.port;
  if (port == 0) {
    port = server.bind_to_any_port(o.bind);
  } else if (!server.bind_to_port(o.bind, port)) {
    port = -1;
  }
  if (port < 0)
    throw UserError("--port " + std::to_string(o.port),
                    "cannot listen on " + o.bind + ":" + std::to_string(o.port),
                    "is another server there? give another --port, or 0 for any free one");
  if (o.bind != "127.0.0.1" && o.bind != "localhost" && o.bind != "::1")
    std::printf(
        "warning: serving on %s, beyond this machine: anyone who can reach it and has "
        "the token can confirm and abort the session\n",
        o.bind.c_str());
  std::printf("live view of acqd at %s: http://%s:%d/?token=%s\n", o.socket.c_str(),
              o.bind == "0.0.0.0" ? "127.0.0.1" : o.bind.c_str(), port, o.token.c_str());
  std::fflush(stdout);
  // SIGINT and SIGTERM end the server from a thread of their own (a handler may not call stop).
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread stopper([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    server.stop();
  });
  server.listen_after_bind();
  if (stopper.joinable()) {
    pthread_kill(stopper.native_handle(), SIGTERM);
    stopper.join();
  }
  return 0;
}

}  // namespace acq
