#include <catch2/catch.hpp>
#include <fstream>

#include "brdf/directions.h"
#include "core/angles.h"
#include "test_helpers.h"

using namespace acq;

TEST_CASE("the seed's 20 directions read as published", "[directions]") {
  const auto d = ReadDirectionsTsv(test::DataPath("directions/seed_directions_20.tsv"));
  REQUIRE(d.size() == 20);
  CHECK(RadToDeg(d[0].angles.theta_d) == Approx(30));
  CHECK(RadToDeg(d[19].angles.theta_h) == Approx(63));
  CHECK(RadToDeg(d[19].angles.phi_d) == Approx(129));
  const auto bins = BinsOf(d);
  // theta_h 63 -> floor(sqrt(63/90) * 90) = 75; theta_d 34 -> 34; phi_d 129 -> 129.
  CHECK(bins[19] == merl::BinIndex{75, 34, 129}.Flat());
}

TEST_CASE("bad direction files name file:line and the problem", "[directions]") {
  test::TempDir dir;
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const std::string below =
      write("below.tsv", "# c\ntheta_h\ttheta_d\tphi_d\n0\t30\t0\n60\t50\t0\n");
  CHECK_THROWS_WITH(ReadDirectionsTsv(below),
                    Catch::Contains("below.tsv:4") && Catch::Contains("below the horizon"));
  const std::string bad = write("bad.tsv", "theta_h\ttheta_d\tphi_d\n0\tthirty\t0\n");
  CHECK_THROWS_WITH(ReadDirectionsTsv(bad),
                    Catch::Contains("bad.tsv:2") && Catch::Contains("expected 3 numbers"));
  const std::string range = write("range.tsv", "theta_h\ttheta_d\tphi_d\n95\t3\t0\n");
  CHECK_THROWS_WITH(ReadDirectionsTsv(range),
                    Catch::Contains("range.tsv:2") && Catch::Contains("out of range"));
  const std::string header = write("header.tsv", "0\t30\t0\n");
  CHECK_THROWS_WITH(ReadDirectionsTsv(header), Catch::Contains("header"));
  const std::string empty = write("empty.tsv", "theta_h\ttheta_d\tphi_d\n");
  CHECK_THROWS_WITH(ReadDirectionsTsv(empty), Catch::Contains("no directions"));
}

TEST_CASE("random directions: deterministic, valid, and they round-trip through TSV",
          "[directions]") {
  const auto a = RandomDirections(25, 42), b = RandomDirections(25, 42),
             c = RandomDirections(25, 43);
  CHECK(BinsOf(a) == BinsOf(b));
  CHECK(BinsOf(a) != BinsOf(c));
  for (std::size_t bin : BinsOf(a)) CHECK(merl::Geometry().valid[bin]);
  test::TempDir dir;
  WriteDirectionsTsv(a, dir / "r.tsv", "test");
  CHECK(BinsOf(ReadDirectionsTsv(dir / "r.tsv")) == BinsOf(a));
}
