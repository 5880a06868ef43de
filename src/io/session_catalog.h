// The session's catalog (issue 8; docs/session-and-plan.md): which steps are done and which
// frames exist, in SQLite, written so that a crash at any instant (kill -9, power cut) leaves a
// consistent session. The rules: a file is written under a temporary name and renamed into
// place first; its row (with the file's SHA-256) is committed after; a row exists only for a
// complete file. On resume, VerifyAndRepair() checks every row's file against its checksum and
// removes the frame file that no row names (a crash between the rename and the commit), so
// nothing is taken as done that is not, and nothing is recorded twice. It deletes only what acqd
// writes (frame files by their name, docs/session-and-plan.md): any other file is left and
// reported (issue 22). More than one unrecorded frame cannot come from a crash (frames are
// recorded one at a time): a catalog that lost its rows is refused, never "repaired" by deleting
// the frames; `acq session repair` rebuilds it from the frames' own metadata.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/session_vocabulary.h"

struct sqlite3;

namespace acq {

struct CatalogFrame {
  Step step = Step::kSample;
  int pose = 0;  // index in the visiting order (or capture number)
  double exposure_us = 0;
  std::string path;  // relative to the session directory (frames/...)
  std::string sha256;
  std::int64_t bytes = 0;
};

class SessionCatalog {
 public:
  // Opens or creates <session>/catalog.sqlite (WAL journal, full synchronisation: a committed
  // row survives a power cut). Throws UserError naming the file when it cannot.
  explicit SessionCatalog(const std::string& session_dir);
  ~SessionCatalog();
  SessionCatalog(const SessionCatalog&) = delete;
  SessionCatalog& operator=(const SessionCatalog&) = delete;

  const std::string& directory() const { return dir_; }
  // Records a frame whose file is already in place; computes its checksum and size. Throws
  // UserError when the same (step, pose, exposure) is already recorded: a frame is never
  // recorded twice.
  void RecordFrame(CatalogFrame frame);
  bool HasFrame(Step step, int pose, double exposure_us) const;
  // Throws UserError for a row whose step this build does not know (a catalog from elsewhere).
  std::vector<CatalogFrame> Frames() const;
  // The frames of one pose of a step, in recording order (an indexed query: the capture asks
  // after every pose, and the whole list grows with the session).
  std::vector<CatalogFrame> FramesOf(Step step, int pose) const;

  void MarkStepDone(Step step);
  bool StepDone(Step step) const;
  void Event(const std::string& level, const std::string& message);
  std::vector<std::pair<std::string, std::string>> Events() const;  // (level, message), in order
  // Choices made while capturing that a resumed run must repeat, not make again (the automatic
  // bracket chosen at a pose): recorded once (UserError on a second time), "" when not made.
  void RecordDecision(const std::string& key, const std::string& value);
  std::string Decision(const std::string& key) const;
  std::map<std::string, std::string> Decisions() const;  // all, by key

  struct Repair {
    int verified = 0;
    std::vector<std::string> bad;      // rows whose file was missing or changed: removed
    std::vector<std::string> orphans;  // acqd's files under frames/ that no row names: removed
    std::vector<std::string> unknown;  // other files under frames/: left alone
  };
  // Throws UserError (before removing anything) when frames/ holds more than one frame file the
  // catalog does not record.
  Repair VerifyAndRepair();
  // The frame files under frames/ that no row names (names relative to the session).
  std::vector<std::string> UnrecordedFrames() const;
  // A consistent copy of the catalog as <session_dir>/catalog.sqlite (SQLite's VACUUM INTO: the
  // WAL's committed rows included), for a session copied to be processed elsewhere (issue 21).
  void CopyTo(const std::string& session_dir) const;

 private:
  void Exec(const char* sql) const;
  std::string dir_, path_;
  sqlite3* db_ = nullptr;
};

// The session's name for a frame file ("frames/sample_007_16000us.exr"), and whether a file
// name under frames/ is one acqd writes (a frame, or one being written: ".partial").
std::string FrameFileName(Step step, int pose, double exposure_us);
// The decision key of the automatic bracket chosen at a pose ("bracket/sample/7"), and the
// bracket's text as the decision and each frame's `bracket_us` attribute hold it (exposures in
// microseconds, space-separated, exact to the last bit).
std::string BracketDecisionKey(Step step, int pose);
std::string BracketText(const std::vector<double>& exposures_us);
std::vector<double> ParseBracketText(const std::string& text);
bool IsFrameFileName(const std::string& filename);

// Writes `bytes` to `path` as the catalog requires: to path + ".partial", flushed to disk, then
// renamed over `path` (atomic on POSIX), then the directory synced.
void WriteFileAtomically(const std::string& path, const void* bytes, std::size_t n);

}  // namespace acq
