#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "core/error.h"
#include "core/sha256.h"
#include "io/session_catalog.h"
#include "test_helpers.h"

using namespace acq;
namespace fs = std::filesystem;

namespace {

// A frame's bytes: deterministic from its index, 64 kB, so a torn write is detectable.
std::string FrameBytes(int i) {
  std::string s(65536, '\0');
  for (std::size_t k = 0; k < s.size(); ++k) s[k] = char((k * 31 + std::size_t(i) * 7) & 0xFF);
  return s;
}

std::string FramePath(int i) {
  return FrameFileName(Step::kSample, i, 1000);
}

// What the sequencer does for each frame, skipping what the catalog says is done.
void CaptureFrames(const std::string& dir, int count) {
  SessionCatalog catalog(dir);
  for (int i = 0; i < count; ++i) {
    if (catalog.HasFrame(Step::kSample, i, 1000)) continue;
    const std::string bytes = FrameBytes(i);
    WriteFileAtomically((fs::path(dir) / FramePath(i)).string(), bytes.data(), bytes.size());
    catalog.RecordFrame({Step::kSample, i, 1000, FramePath(i), "", 0});
  }
  catalog.MarkStepDone(Step::kSample);
}

}  // namespace

TEST_CASE("sha256: the standard's test vectors", "[catalog]") {
  Sha256 empty;
  CHECK(empty.HexDigest() == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  Sha256 abc;
  abc.Update("abc", 3);
  CHECK(abc.HexDigest() == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  Sha256 two_blocks;  // 56 bytes: the padding spills into a second block
  const std::string s = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  two_blocks.Update(s.data(), s.size());
  CHECK(two_blocks.HexDigest() ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST_CASE("catalog: frames recorded once, steps, damaged and unrecorded files repaired",
          "[catalog]") {
  const test::TempDir tmp;
  const std::string dir = tmp / "session";
  {
    SessionCatalog catalog(dir);
    const std::string bytes = FrameBytes(0);
    WriteFileAtomically(dir + "/" + FramePath(0), bytes.data(), bytes.size());
    catalog.RecordFrame({Step::kSample, 0, 1000, FramePath(0), "", 0});
    CHECK(catalog.HasFrame(Step::kSample, 0, 1000));
    CHECK_FALSE(catalog.HasFrame(Step::kSample, 0, 8000));
    CHECK_THROWS_WITH(catalog.RecordFrame({Step::kSample, 0, 1000, FramePath(0), "", 0}),
                      Catch::Contains("already recorded"));
    CHECK_FALSE(catalog.StepDone(Step::kSample));
    catalog.MarkStepDone(Step::kSample);
    CHECK(catalog.StepDone(Step::kSample));
    const std::string other = FrameBytes(1);
    WriteFileAtomically(dir + "/" + FramePath(1), other.data(), other.size());
    catalog.RecordFrame({Step::kSample, 1, 1000, FramePath(1), "", 0});
    // One pose's frames, by query: another exposure of pose 0, and another step's pose 0.
    WriteFileAtomically(dir + "/frames/long.raw", bytes.data(), bytes.size());
    catalog.RecordFrame({Step::kSample, 0, 8000, "frames/long.raw", "", 0});
    WriteFileAtomically(dir + "/frames/white.raw", bytes.data(), bytes.size());
    catalog.RecordFrame({Step::kSpectralon, 0, 1000, "frames/white.raw", "", 0});
    const std::vector<CatalogFrame> pose0 = catalog.FramesOf(Step::kSample, 0);
    REQUIRE(pose0.size() == 2);
    CHECK(pose0[0].exposure_us == 1000);  // in recording order
    CHECK(pose0[1].path == "frames/long.raw");
    CHECK(catalog.FramesOf(Step::kSample, 1).size() == 1);
    CHECK(catalog.FramesOf(Step::kSpectralon, 0).size() == 1);
    CHECK(catalog.FramesOf(Step::kSample, 2).empty());
  }
  // Damage one recorded frame and leave an unrecorded one (a crash after the rename).
  {
    std::FILE* f = std::fopen((dir + "/" + FramePath(1)).c_str(), "r+b");
    REQUIRE(f);
    std::fputc('X', f);
    std::fclose(f);
    const std::string stray = FrameBytes(2);
    WriteFileAtomically(dir + "/" + FramePath(2), stray.data(), stray.size());
  }
  SessionCatalog reopened(dir);
  const SessionCatalog::Repair r = reopened.VerifyAndRepair();
  CHECK(r.verified == 3);
  REQUIRE(r.bad.size() == 1);
  CHECK(r.bad[0] == FramePath(1));
  REQUIRE(r.orphans.size() == 1);
  CHECK(r.orphans[0] == fs::path(FramePath(2)).filename().string());
  CHECK(reopened.Frames().size() == 3);
  CHECK(reopened.StepDone(Step::kSample));
}

// Issue 22: the catalog deletes only what acqd writes, and never "repairs" a catalog that lost
// its rows by deleting the frames.
TEST_CASE("catalog: files acqd did not write are left; a catalog that lost rows is refused",
          "[catalog]") {
  const test::TempDir tmp;
  const std::string dir = tmp / "session";
  {
    SessionCatalog catalog(dir);
    for (int i = 0; i < 3; ++i) {
      const std::string bytes = FrameBytes(i);
      WriteFileAtomically(dir + "/" + FramePath(i), bytes.data(), bytes.size());
      catalog.RecordFrame({Step::kSample, i, 1000, FramePath(i), "", 0});
    }
  }
  std::ofstream(dir + "/frames/notes.txt") << "mine";
  std::ofstream(dir + "/frames/sample_099_1000us.exr.bak") << "mine too";
  fs::create_directories(dir + "/frames/old");
  {
    SessionCatalog catalog(dir);
    const SessionCatalog::Repair r = catalog.VerifyAndRepair();
    CHECK(r.verified == 3);
    CHECK(r.orphans.empty());
    CHECK(r.unknown.size() == 3);
    CHECK(fs::exists(dir + "/frames/notes.txt"));
    CHECK(fs::exists(dir + "/frames/sample_099_1000us.exr.bak"));
    CHECK(fs::exists(dir + "/frames/old"));
  }
  // The catalog deleted (or emptied): three frames it does not record, refused, nothing deleted.
  for (const char* f : {"catalog.sqlite", "catalog.sqlite-wal", "catalog.sqlite-shm"})
    fs::remove(dir + "/" + f);
  SessionCatalog fresh(dir);
  CHECK(fresh.UnrecordedFrames().size() == 3);
  CHECK_THROWS_WITH(fresh.VerifyAndRepair(), Catch::Contains("does not record 3 frames") &&
                                                 Catch::Contains("acq session repair"));
  for (int i = 0; i < 3; ++i) CHECK(fs::exists(dir + "/" + FramePath(i)));
}

TEST_CASE("catalog: kill -9 at any instant, then resume: every frame once, none lost",
          "[catalog][crash]") {
  // A child process captures 60 frames (each written to a temporary name, fsynced, renamed,
  // then recorded); the parent kills it with SIGKILL after a different delay each round, then
  // verifies and resumes as acqd --resume does. The kill lands before, during and after the
  // write, the rename and the commit of some frame; whatever the instant, the resumed session
  // must hold exactly frames 0..59, each once, each with its bytes.
  const int frames = 60;
  const test::TempDir tmp;
  for (int round = 0; round < 6; ++round) {
    const std::string dir = tmp / ("session_" + std::to_string(round));
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      try {
        CaptureFrames(dir, frames);
      } catch (...) {
        _exit(3);
      }
      _exit(0);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5 + 17 * round));
    kill(child, SIGKILL);
    int status = 0;
    waitpid(child, &status, 0);
    SessionCatalog catalog(dir);
    const SessionCatalog::Repair repair = catalog.VerifyAndRepair();
    CHECK(repair.bad.empty());  // a row never exists for a file that is not complete
    const std::size_t before = catalog.Frames().size();
    UNSCOPED_INFO("round " << round << ": " << before << " frames done at the kill, "
                           << repair.orphans.size() << " unrecorded files removed");
    CaptureFrames(dir, frames);  // resume
    const std::vector<CatalogFrame> done = catalog.Frames();
    REQUIRE(done.size() == std::size_t(frames));
    for (int i = 0; i < frames; ++i) {
      CHECK(done[std::size_t(i)].pose == i);  // in order, each once
      const std::string expected = FrameBytes(i);
      Sha256 sha;
      sha.Update(expected.data(), expected.size());
      CHECK(done[std::size_t(i)].sha256 == sha.HexDigest());
    }
    std::size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir + "/frames")) files += e.is_regular_file();
    CHECK(files == std::size_t(frames));  // no stray partial or duplicate file
    CHECK(catalog.StepDone(Step::kSample));
  }
}
