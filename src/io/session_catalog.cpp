#include "io/session_catalog.h"

#include <map>

#include <fcntl.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/sha256.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

// A prepared statement, finalised on every path out.
class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const std::string& where) : where_(where) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK)
      throw UserError(where, std::string("catalog query failed: ") + sqlite3_errmsg(db));
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement& Bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.c_str(), -1, SQLITE_TRANSIENT);
    return *this;
  }
  Statement& Bind(int i, double v) {
    sqlite3_bind_double(s_, i, v);
    return *this;
  }
  Statement& Bind(int i, std::int64_t v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  bool Step() {
    const int r = sqlite3_step(s_);
    if (r == SQLITE_ROW) return true;
    if (r == SQLITE_DONE) return false;
    throw UserError(where_, std::string("catalog: ") + sqlite3_errmsg(sqlite3_db_handle(s_)),
                    r == SQLITE_CONSTRAINT ? "" : "check the disk (full? read-only?)");
  }
  std::string Text(int i) const {
    const unsigned char* t = sqlite3_column_text(s_, i);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  double Real(int i) const { return sqlite3_column_double(s_, i); }
  std::int64_t Int(int i) const { return sqlite3_column_int64(s_, i); }

 private:
  sqlite3_stmt* s_ = nullptr;
  std::string where_;
};

void SyncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

void WriteFileAtomically(const std::string& path, const void* bytes, std::size_t n) {
  const std::string partial = path + ".partial";
  const int fd = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) throw UserError(partial, "cannot be created", "check the disk and its permissions");
  const auto* p = static_cast<const char*>(bytes);
  std::size_t left = n;
  while (left > 0) {
    const ssize_t w = ::write(fd, p, left);
    if (w <= 0) {
      ::close(fd);
      throw UserError(partial, "write failed", "is the disk full?");
    }
    p += w, left -= std::size_t(w);
  }
  ::fsync(fd);
  ::close(fd);
  if (std::rename(partial.c_str(), path.c_str()) != 0)
    throw UserError(path, "cannot be renamed into place");
  SyncDirectory(fs::path(path).parent_path());
}

SessionCatalog::SessionCatalog(const std::string& session_dir)
    : dir_(session_dir), path_((fs::path(session_dir) / "catalog.sqlite").string()) {
  std::error_code ec;
  fs::create_directories(fs::path(session_dir) / "frames", ec);
  if (ec) throw UserError(session_dir, "cannot create the session directory: " + ec.message());
  // Serialized: the frame writer records frames on its own thread (session/frame_writer.h)
  // while the capture's thread reads decisions and writes events on this connection.
  if (sqlite3_open_v2(path_.c_str(), &db_,
                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                      nullptr) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw UserError(path_, "cannot open the catalog: " + why);
  }
  sqlite3_busy_timeout(db_, 5000);
  Exec("PRAGMA journal_mode=WAL");
  Exec("PRAGMA synchronous=FULL");
  Exec(
      "CREATE TABLE IF NOT EXISTS frames (step TEXT NOT NULL, pose INTEGER NOT NULL,"
      " exposure_us REAL NOT NULL, path TEXT NOT NULL UNIQUE, sha256 TEXT NOT NULL,"
      " bytes INTEGER NOT NULL, recorded TEXT DEFAULT CURRENT_TIMESTAMP,"
      " UNIQUE (step, pose, exposure_us))");
  Exec(
      "CREATE TABLE IF NOT EXISTS steps (step TEXT PRIMARY KEY,"
      " done TEXT DEFAULT CURRENT_TIMESTAMP)");
  Exec(
      "CREATE TABLE IF NOT EXISTS decisions (key TEXT PRIMARY KEY, value TEXT NOT NULL,"
      " decided TEXT DEFAULT CURRENT_TIMESTAMP)");
  Exec(
      "CREATE TABLE IF NOT EXISTS events (time TEXT DEFAULT CURRENT_TIMESTAMP,"
      " level TEXT NOT NULL, message TEXT NOT NULL)");
}

SessionCatalog::~SessionCatalog() {
  sqlite3_close(db_);
}

void SessionCatalog::Exec(const char* sql) const {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string why = error ? error : "unknown";
    sqlite3_free(error);
    throw UserError(path_, "catalog: " + why, "check the disk; is the catalog from another acqd?");
  }
}

void SessionCatalog::RecordFrame(CatalogFrame frame) {
  const std::string full = (fs::path(dir_) / frame.path).string();
  frame.sha256 = Sha256OfFile(full);
  frame.bytes = std::int64_t(fs::file_size(full));
  if (HasFrame(frame.step, frame.pose, frame.exposure_us))
    throw UserError(path_, std::string("frame ") + ToString(frame.step) + " pose " +
                               std::to_string(frame.pose) + " at " +
                               std::to_string(frame.exposure_us) + " us is already recorded");
  Statement s(db_,
              "INSERT INTO frames (step, pose, exposure_us, path, sha256, bytes)"
              " VALUES (?, ?, ?, ?, ?, ?)",
              path_);
  s.Bind(1, ToString(frame.step)).Bind(2, std::int64_t(frame.pose)).Bind(3, frame.exposure_us);
  s.Bind(4, frame.path).Bind(5, frame.sha256).Bind(6, frame.bytes).Step();
}

bool SessionCatalog::HasFrame(Step step, int pose, double exposure_us) const {
  Statement s(db_, "SELECT 1 FROM frames WHERE step = ? AND pose = ? AND exposure_us = ?", path_);
  s.Bind(1, ToString(step)).Bind(2, std::int64_t(pose)).Bind(3, exposure_us);
  return s.Step();
}

namespace {

std::vector<CatalogFrame> FrameRows(Statement& s, const std::string& where) {
  std::vector<CatalogFrame> out;
  while (s.Step()) {
    const std::optional<Step> step = ParseStep(s.Text(0));
    if (!step)
      throw UserError(
          where, "a frame row names the step '" + s.Text(0) + "', which acqd does not know",
          "was the catalog written by another program? `acq session repair` rebuilds it");
    out.push_back({*step, int(s.Int(1)), s.Real(2), s.Text(3), s.Text(4), s.Int(5)});
  }
  return out;
}

}  // namespace

std::vector<CatalogFrame> SessionCatalog::Frames() const {
  Statement s(db_, "SELECT step, pose, exposure_us, path, sha256, bytes FROM frames ORDER BY rowid",
              path_);
  return FrameRows(s, path_);
}

std::vector<CatalogFrame> SessionCatalog::FramesOf(Step step, int pose) const {
  Statement s(db_,
              "SELECT step, pose, exposure_us, path, sha256, bytes FROM frames "
              "WHERE step = ? AND pose = ? ORDER BY rowid",
              path_);
  s.Bind(1, ToString(step)).Bind(2, std::int64_t(pose));
  return FrameRows(s, path_);
}

void SessionCatalog::MarkStepDone(Step step) {
  Statement(db_, "INSERT OR IGNORE INTO steps (step) VALUES (?)", path_)
      .Bind(1, ToString(step))
      .Step();
}

void SessionCatalog::RecordDecision(const std::string& key, const std::string& value) {
  Statement(db_, "INSERT INTO decisions (key, value) VALUES (?, ?)", path_)
      .Bind(1, key)
      .Bind(2, value)
      .Step();
}

std::string SessionCatalog::Decision(const std::string& key) const {
  Statement s(db_, "SELECT value FROM decisions WHERE key = ?", path_);
  s.Bind(1, key);
  return s.Step() ? s.Text(0) : "";
}

std::map<std::string, std::string> SessionCatalog::Decisions() const {
  Statement s(db_, "SELECT key, value FROM decisions", path_);
  std::map<std::string, std::string> out;
  while (s.Step()) out[s.Text(0)] = s.Text(1);
  return out;
}

bool SessionCatalog::StepDone(Step step) const {
  Statement s(db_, "SELECT 1 FROM steps WHERE step = ?", path_);
  s.Bind(1, ToString(step));
  return s.Step();
}

void SessionCatalog::Event(const std::string& level, const std::string& message) {
  Statement(db_, "INSERT INTO events (level, message) VALUES (?, ?)", path_)
      .Bind(1, level)
      .Bind(2, message)
      .Step();
}

std::vector<std::pair<std::string, std::string>> SessionCatalog::Events() const {
  Statement s(db_, "SELECT level, message FROM events ORDER BY rowid", path_);
  std::vector<std::pair<std::string, std::string>> out;
  while (s.Step()) out.emplace_back(s.Text(0), s.Text(1));
  return out;
}

std::string FrameFileName(Step step, int pose, double exposure_us) {
  char name[128];
  std::snprintf(name, sizeof name, "frames/%s_%03d_%.0fus.exr", ToString(step), pose, exposure_us);
  return name;
}

std::string BracketDecisionKey(Step step, int pose) {
  return std::string("bracket/") + ToString(step) + "/" + std::to_string(pose);
}

std::string BracketText(const std::vector<double>& exposures_us) {
  std::ostringstream out;
  out.precision(17);
  for (double t : exposures_us) out << t << ' ';
  return out.str();
}

std::vector<double> ParseBracketText(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> exposures;
  for (double t; in >> t;) exposures.push_back(t);
  return exposures;
}

bool IsFrameFileName(const std::string& filename) {
  static const std::regex frame("[a-z_]+_[0-9]{3,}_[0-9]+us\\.exr(\\.partial)?");
  return std::regex_match(filename, frame);
}

std::vector<std::string> SessionCatalog::UnrecordedFrames() const {
  std::set<std::string> named;
  for (const CatalogFrame& f : Frames()) named.insert(fs::path(f.path).filename().string());
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(dir_) / "frames", ec)) {
    const std::string name = e.path().filename().string();
    if (!named.count(name) && IsFrameFileName(name) && name.find(".partial") == std::string::npos)
      out.push_back("frames/" + name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

SessionCatalog::Repair SessionCatalog::VerifyAndRepair() {
  const std::vector<std::string> unrecorded = UnrecordedFrames();
  if (unrecorded.size() > 1)
    throw UserError(path_,
                    "the catalog does not record " + std::to_string(unrecorded.size()) +
                        " frames that lie in " + dir_ + "/frames (" + unrecorded.front() +
                        ", ...): a crash leaves at most one; the catalog was emptied, replaced "
                        "or lost rows",
                    "nothing was deleted; rebuild the catalog from the frames' own metadata "
                    "with `acq session repair " +
                        dir_ + "`, then run acqd again");
  Repair r;
  std::set<std::string> named;
  for (const CatalogFrame& f : Frames()) {
    const fs::path full = fs::path(dir_) / f.path;
    std::error_code ec;
    const bool ok = fs::is_regular_file(full, ec) &&
                    std::int64_t(fs::file_size(full, ec)) == f.bytes &&
                    Sha256OfFile(full.string()) == f.sha256;
    if (ok) {
      ++r.verified;
      named.insert(full.lexically_normal().string());
      continue;
    }
    r.bad.push_back(f.path);
    Statement(db_, "DELETE FROM frames WHERE path = ?", path_).Bind(1, f.path).Step();
    fs::remove(full, ec);
  }
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(dir_) / "frames", ec)) {
    if (named.count(e.path().lexically_normal().string())) continue;
    const std::string name = e.path().filename().string();
    if (!IsFrameFileName(name) || !e.is_regular_file()) {
      r.unknown.push_back(name);  // not acqd's: left where it is
      continue;
    }
    r.orphans.push_back(name);
    fs::remove(e.path(), ec);
  }
  if (!r.bad.empty() || !r.orphans.empty())
    Event("warning", "resume: " + std::to_string(r.bad.size()) + " damaged frames dropped, " +
                         std::to_string(r.orphans.size()) + " unrecorded files removed");
  if (!r.unknown.empty())
    Event("warning", "frames/ holds " + std::to_string(r.unknown.size()) +
                         " files acqd did not write (left alone), e.g. " + r.unknown.front());
  return r;
}

void SessionCatalog::CopyTo(const std::string& session_dir) const {
  const std::string target = session_dir + "/catalog.sqlite";
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(db_, "VACUUM INTO ?", -1, &stmt, nullptr) != SQLITE_OK)
    throw UserError(path_, sqlite3_errmsg(db_), "check the session's catalog");
  sqlite3_bind_text(stmt, 1, target.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(stmt);
  sqlite3_finalize(stmt);
  if (rc != SQLITE_DONE)
    throw UserError(target, std::string("cannot copy the catalog here: ") + sqlite3_errmsg(db_),
                    "give a new, writable output folder");
}

}  // namespace acq
