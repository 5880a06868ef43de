// The frame writer (session/frame_writer.h): frames written and recorded off the capture's
// thread, in order, each file complete before its row; markers run after the frames before them;
// a failure to write comes back to the capture's thread; what is queued is written at the end.
#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hw/frame_file.h"
#include "io/float_planes_exr.h"
#include "io/session_catalog.h"
#include "session/frame_writer.h"
#include "session/pose_hdr.h"
#include "test_helpers.h"

using namespace acq;
namespace fs = std::filesystem;

namespace {

Frame TestFrame(int i) {
  Frame f;
  f.width = 64;
  f.height = 48;
  f.exposure_us = 1000 + i;
  f.pixels.assign(std::size_t(f.width) * f.height, std::uint16_t(i));
  return f;
}

CatalogFrame Row(int pose) {
  return {
      Step::kSample, pose, 1000.0 + pose, FrameFileName(Step::kSample, pose, 1000 + pose), "", 0};
}

}  // namespace

TEST_CASE("frame writer: in order, markers after their frames, all written at the end",
          "[session]") {
  const test::TempDir tmp;
  fs::create_directories(tmp / "frames");
  SessionCatalog catalog(tmp / "");
  std::vector<int> recorded_at_marker;
  {
    FrameWriter writer(catalog, 2);  // a small queue: Write() must wait, never drop
    for (int i = 0; i < 8; ++i) {
      writer.Write(TestFrame(i), {{"pose", std::to_string(i)}}, Row(i));
      // Runs on the writer once frame i is recorded: every frame up to it is in the catalog.
      writer.After([&, i] {
        recorded_at_marker.push_back(int(catalog.Frames().size()));
        CHECK(catalog.HasFrame(Step::kSample, i, 1000 + i));
      });
    }
    writer.Flush();
    CHECK(catalog.Frames().size() == 8);
    for (int i = 8; i < 12; ++i) writer.Write(TestFrame(i), {}, Row(i));
  }  // the destructor writes and records the four still queued
  const std::vector<CatalogFrame> frames = catalog.Frames();
  REQUIRE(frames.size() == 12);
  for (int i = 0; i < 12; ++i) {
    CHECK(frames[std::size_t(i)].pose == i);  // in the order written
    const Frame back = ReadFrameExr(tmp / frames[std::size_t(i)].path);
    CHECK(back.pixels == TestFrame(i).pixels);
  }
  REQUIRE(recorded_at_marker.size() == 8);
  for (int i = 0; i < 8; ++i) CHECK(recorded_at_marker[std::size_t(i)] >= i + 1);
  CHECK(catalog.VerifyAndRepair().verified == 12);
}

TEST_CASE("frame writer: a failure to write comes back to the capture, nothing after it is written",
          "[session]") {
  const test::TempDir tmp;
  SessionCatalog catalog(tmp / "");
  fs::remove_all(tmp / "frames");
  std::ofstream(tmp / "frames") << "not a folder";  // every frame write fails (root or not)
  FrameWriter writer(catalog);
  writer.Write(TestFrame(0), {}, Row(0));
  CHECK_THROWS(writer.Flush());
  // Once failed, always failed: the capture stops at its next frame.
  CHECK_THROWS(writer.Write(TestFrame(1), {}, Row(1)));
  CHECK_THROWS(writer.After([] {}));
  CHECK(catalog.Frames().empty());
}

TEST_CASE("pose hdr: reused when merged by this rule, merged again when not", "[session]") {
  // A pose's hdr file is derived data: one merged by an earlier rule (before 2026-12-03 the merge
  // dropped values under a noise floor) must not be mixed into a session merged by this one.
  const test::TempDir tmp;
  fs::create_directories(tmp / "frames");
  SessionCatalog catalog(tmp / "");
  {
    FrameWriter writer(catalog, 2);
    writer.Write(TestFrame(100), {{"arms_measured_deg", "10 20 30 40"}}, Row(0));
  }
  const std::vector<CatalogFrame> frames = catalog.Frames();
  double seconds = 0;
  const PoseHdr first = MergePose(tmp / "", Step::kSample, 0, frames, &seconds);
  const std::string path = tmp / ("hdr/" + PoseName(Step::kSample, 0) + ".exr");
  FloatPlanes file = ReadFloatPlanesExr(path);
  CHECK(file.attributes["merge"] == kHdrMergeRule);
  // Read back, not merged again: a plane changed in the file comes back changed.
  file.planes["flag"][0] = float(kHdrSaturated);
  WriteFloatPlanesExr(path, file);
  CHECK(MergePose(tmp / "", Step::kSample, 0, frames, &seconds).hdr.flag[0] == kHdrSaturated);
  // The same file recorded as merged by another rule: merged again from the frames.
  file.attributes["merge"] = "an earlier rule";
  WriteFloatPlanesExr(path, file);
  const PoseHdr again = MergePose(tmp / "", Step::kSample, 0, frames, &seconds);
  CHECK(again.hdr.flag[0] == kHdrOk);
  CHECK(again.hdr.radiance == first.hdr.radiance);
  CHECK(ReadFloatPlanesExr(path).attributes["merge"] == kHdrMergeRule);
}
