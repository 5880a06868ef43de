#include <catch2/catch.hpp>

#include <ImfInputFile.h>
#include <ImfStandardAttributes.h>
#include <cmath>
#include <filesystem>
#include <limits>

#include "io/svbrdf_map.h"
#include "test_helpers.h"

using namespace acq;

TEST_CASE("SVBRDF map: written band by band, read back identical, with its metadata", "[map]") {
  test::TempDir dir;
  SvbrdfMapInfo info;
  info.width = 7;
  info.height = 5;
  info.components = 3;
  info.eta = 40;
  info.lookup = "nearest";
  info.basis = "b.acqb";
  info.basis_crc32 = 0xdeadbeef;
  info.camera_model = "ref.cameramodel";
  info.pixel_size_mm = 0.25;
  info.pixel_spread_px = 0.28;
  info.source = "test";
  const std::vector<std::string> names = SvbrdfChannelNames(3);
  REQUIRE(names.size() == 20);
  CHECK(names[0] == "R.c00");
  CHECK(names[8] == "B.c02");
  CHECK(names[12] == "residual");
  CHECK(names[14] == "departure");
  CHECK(names[15] == "normal.x");
  CHECK(names[18] == "normal_status");
  CHECK(names[19] == "normal_uncertainty_deg");
  auto value = [](int c, int x, int y) { return float(c * 1000 + y * 10 + x) + 0.5f; };
  {
    SvbrdfMapWriter w(dir / "m.exr", info);
    for (int y0 : {0, 2, 4}) {  // bands of 2, 2 and 1 rows
      const int rows = std::min(2, 5 - y0);
      std::vector<std::vector<float>> planes(20, std::vector<float>(rows * 7));
      for (int c = 0; c < 20; ++c)
        for (int y = 0; y < rows; ++y)
          for (int x = 0; x < 7; ++x) planes[c][y * 7 + x] = value(c, x, y0 + y);
      planes[11][0] = std::numeric_limits<float>::infinity();  // a condition of inf survives
      std::vector<const float*> p;
      for (auto& v : planes) p.push_back(v.data());
      w.WriteRows(rows, p);
    }
    CHECK_FALSE(std::filesystem::exists(dir / "m.exr"));  // only complete maps appear
    w.Finish();
  }
  const SvbrdfMap map = ReadSvbrdfMap(dir / "m.exr");
  CHECK(map.info.width == 7);
  CHECK(map.info.height == 5);
  CHECK(map.info.components == 3);
  CHECK(map.info.basis_crc32 == 0xdeadbeef);
  CHECK(map.info.camera_model == "ref.cameramodel");
  CHECK(map.info.pixel_size_mm == 0.25);
  CHECK(map.info.pixel_spread_px == 0.28);
  CHECK(map.Coefficients(3, 4, 1) ==
        std::vector<float>{value(3, 3, 4), value(4, 3, 4), value(5, 3, 4)});
  CHECK(map.Plane("valid", 6, 1) == value(9, 6, 1));
  CHECK(std::isinf(map.Plane("condition", 0, 2)));
  CHECK(map.Plane("group", 2, 3) == value(13, 2, 3));
  CHECK(map.Plane("normal.z", 2, 3) == value(17, 2, 3));
  CHECK(map.Plane("normal_uncertainty_deg", 1, 4) == value(19, 1, 4));
  CHECK(map.info.method == "independent");
  // The colour space is stated for any OpenEXR reader: Rec. 709's primaries and D65 white.
  const Imf::InputFile file((dir / "m.exr").c_str());
  REQUIRE(Imf::hasChromaticities(file.header()));
  const Imf::Chromaticities c = Imf::chromaticities(file.header());
  CHECK(c.red.x == Approx(0.64));
  CHECK(c.green.y == Approx(0.60));
  CHECK(c.blue.x == Approx(0.15));
  CHECK(c.white.x == Approx(0.3127));
}

TEST_CASE("an unfinished map leaves no file; a foreign EXR is refused", "[map]") {
  test::TempDir dir;
  SvbrdfMapInfo info;
  info.width = 4;
  info.height = 4;
  info.components = 1;
  { SvbrdfMapWriter w(dir / "m.exr", info); }  // abandoned, e.g. by an exception
  CHECK(std::filesystem::is_empty(std::filesystem::path(dir / "")));
  CHECK_THROWS_WITH(ReadSvbrdfMap(dir / "none.exr"), Catch::Contains("none.exr"));
  CHECK_THROWS_WITH(ReadSvbrdfMap(test::DataPath("directions/seed_directions_20.tsv")),
                    Catch::Contains("cannot read the SVBRDF map"));
}

TEST_CASE("a synthetic map written before the row rule is read with its rows turned over",
          "[map]") {
  // Before 2026-12-03 `acq reconstruct synthetic` ran a map's rows to the sample's +y, sessions
  // to -y; only synthetic maps moved. Such a map (no acqRowRule) keeps every pixel's place on
  // the sample when read; a session's map of that age is read as written.
  test::TempDir dir;
  SvbrdfMapInfo info;
  info.width = 3;
  info.height = 4;
  info.components = 1;
  info.rows_to_minus_y = false;  // as written then
  const std::size_t planes = SvbrdfChannelNames(1).size();
  auto write = [&](const std::string& path, const std::string& camera) {
    info.camera_model = camera;
    SvbrdfMapWriter w(path, info);
    std::vector<std::vector<float>> v(planes, std::vector<float>(12));
    for (std::size_t c = 0; c < planes; ++c)
      for (int p = 0; p < 12; ++p) v[c][std::size_t(p)] = float(p);  // row y holds 3y..3y+2
    std::vector<const float*> p;
    for (auto& plane : v) p.push_back(plane.data());
    w.WriteRows(4, p);
    w.Finish();
  };
  write(dir / "synthetic.exr", kSyntheticCameraModel);
  write(dir / "session.exr", "calibration/camera.cameramodel");
  const SvbrdfMap synthetic = ReadSvbrdfMap(dir / "synthetic.exr");
  CHECK(synthetic.info.rows_to_minus_y);
  CHECK(synthetic.info.pixel_spread_px == 0);   // no acqPixelSpreadPx: point sampling
  CHECK(synthetic.Plane("valid", 1, 0) == 10);  // the old last row is the first now
  CHECK(synthetic.Plane("normal.y", 2, 3) == 2);
  CHECK(synthetic.Coefficients(0, 1, 0) == std::vector<float>{6});
  const SvbrdfMap session = ReadSvbrdfMap(dir / "session.exr");
  CHECK_FALSE(session.info.rows_to_minus_y);
  CHECK(session.Plane("valid", 1, 0) == 1);
  // A map written now says so, and is read as written.
  info.rows_to_minus_y = true;
  write(dir / "now.exr", kSyntheticCameraModel);
  CHECK(ReadSvbrdfMap(dir / "now.exr").Plane("valid", 1, 0) == 1);
}
