#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include "brdf/merl_brdf.h"
#include "core/angles.h"
#include "core/error.h"
#include "test_helpers.h"

using namespace acq;

namespace {

MerlBrdf RandomBrdf(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 5000.0);
  MerlBrdf b;
  for (double& v : b.raw) v = u(rng);
  return b;
}

std::string Slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

void WriteRaw(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

}  // namespace

TEST_CASE(".binary write then read is identical", "[merl_io]") {
  test::TempDir dir;
  const MerlBrdf b = RandomBrdf(1);
  WriteMerlBinary(b, dir / "a.binary");
  const MerlBrdf back = ReadMerlBinary(dir / "a.binary");
  REQUIRE(std::memcmp(back.raw.data(), b.raw.data(), b.raw.size() * sizeof(double)) == 0);
}

TEST_CASE(".binary read then write is byte-identical, with the documented layout", "[merl_io]") {
  test::TempDir dir;
  WriteMerlBinary(RandomBrdf(2), dir / "a.binary");
  const std::string first = Slurp(dir / "a.binary");
  WriteMerlBinary(ReadMerlBinary(dir / "a.binary"), dir / "b.binary");
  CHECK(first == Slurp(dir / "b.binary"));
  REQUIRE(first.size() == 12 + 3 * merl::kBins * 8);
  std::int32_t dims[3];
  std::memcpy(dims, first.data(), 12);
  CHECK(dims[0] == 90);
  CHECK(dims[1] == 90);
  CHECK(dims[2] == 180);
}

TEST_CASE("lookup follows MERL's reader: bin of the directions, channel scales", "[merl_io]") {
  MerlBrdf b;
  // theta_h 30, theta_d 30.5, phi_d 90.25 deg (away from bin edges): theta_h index
  // floor(sqrt(30/90) * 90) = 51, theta_d index 30, phi_d index 90.
  const std::size_t bin = merl::BinIndex{51, 30, 90}.Flat();
  b.raw[bin] = 1500.0;
  b.raw[merl::kBins + bin] = 1500.0;
  b.raw[2 * merl::kBins + bin] = 1500.0;
  RusinkiewiczAngles a;
  a.theta_h = DegToRad(30);
  a.theta_d = DegToRad(30.5);
  a.phi_d = DegToRad(90.25);
  a.phi_h = 2.0;  // isotropic: any phi_h reads the same bin
  const DirectionPair d = DirectionsFromRusinkiewicz(a);
  const Eigen::Vector3d in = d.in, out = d.out;
  const auto rgb = b.Lookup(in, out);
  CHECK(rgb[0] == Approx(1.0));
  CHECK(rgb[1] == Approx(1.15));
  CHECK(rgb[2] == Approx(1.66));
  // Reciprocity: swapping light and camera reads the same bin.
  CHECK(b.Lookup(out, in)[0] == Approx(1.0));
}

TEST_CASE("the interpolated lookup runs between bin centres, skipping bins without data",
          "[merl_io]") {
  // Two neighbouring theta_d bins of one theta_h and phi_d hold 1 and 3 (raw 1500 and 4500);
  // every other bin has no data (-1).
  MerlBrdf b;
  const merl::BinIndex low{51, 30, 90}, high{51, 31, 90};
  for (int c = 0; c < 3; ++c) {
    b.raw[c * merl::kBins + low.Flat()] = 1500.0;
    b.raw[c * merl::kBins + high.Flat()] = 4500.0;
  }
  auto directions = [](double theta_h, double theta_d_deg, double phi_d_deg) {
    RusinkiewiczAngles a;
    a.theta_h = theta_h, a.theta_d = DegToRad(theta_d_deg), a.phi_d = DegToRad(phi_d_deg);
    a.phi_h = 1.0;  // isotropic: any
    return DirectionsFromRusinkiewicz(a);
  };
  const double theta_h = merl::BinCentre(low).theta_h;
  auto at = [&](double theta_d_deg) {
    const DirectionPair d = directions(theta_h, theta_d_deg, 90.5);
    return b.LookupInterpolated(d.in, d.out);
  };
  // At a bin centre: that bin's value, as Lookup gives it (the neighbours without data, whose
  // weights the centre's bin takes, change nothing).
  CHECK(at(30.5)[0] == Approx(1.0).epsilon(1e-9));
  CHECK(at(30.5)[2] == Approx(1.66).epsilon(1e-9));
  // A quarter and a half of the way to the next centre (theta_d centres 1 degree apart): linear.
  CHECK(at(30.75)[0] == Approx(1.5).epsilon(1e-9));
  CHECK(at(31.0)[1] == Approx(2.0 * 1.15).epsilon(1e-9));
  // Nearest, by contrast, steps at the bin edge (31 degrees).
  const DirectionPair edge = directions(theta_h, 30.9, 90.5);
  CHECK(b.Lookup(edge.in, edge.out)[0] == Approx(1.0));
  CHECK(b.LookupInterpolated(edge.in, edge.out)[0] == Approx(1.8).epsilon(1e-9));
  // Where no surrounding bin has data: zero, not the -1 marker.
  const DirectionPair far = directions(DegToRad(5), 60, 20);
  CHECK(b.LookupInterpolated(far.in, far.out)[0] == 0.0);
}

TEST_CASE("bad .binary files are refused with the file and the problem named", "[merl_io]") {
  test::TempDir dir;
  WriteMerlBinary(RandomBrdf(3), dir / "good.binary");
  const std::string good = Slurp(dir / "good.binary");

  WriteRaw(dir / "short.binary", good.substr(0, good.size() - 100));
  CHECK_THROWS_WITH(ReadMerlBinary(dir / "short.binary"),
                    Catch::Contains("short.binary") && Catch::Contains("truncated"));

  WriteRaw(dir / "tiny.binary", good.substr(0, 6));
  CHECK_THROWS_WITH(ReadMerlBinary(dir / "tiny.binary"), Catch::Contains("12-byte"));

  std::string dims = good;
  const std::int32_t wrong[3] = {90, 90, 360};
  std::memcpy(dims.data(), wrong, 12);
  WriteRaw(dir / "dims.binary", dims);
  CHECK_THROWS_WITH(ReadMerlBinary(dir / "dims.binary"),
                    Catch::Contains("dims.binary") && Catch::Contains("90 x 90 x 360"));

  std::string nan = good;
  const double bad = std::nan("");
  std::memcpy(nan.data() + 12 + 8 * (merl::kBins + 5), &bad, 8);
  WriteRaw(dir / "nan.binary", nan);
  CHECK_THROWS_WITH(ReadMerlBinary(dir / "nan.binary"), Catch::Contains("nan.binary") &&
                                                            Catch::Contains("channel G") &&
                                                            Catch::Contains("phi_d 5"));

  WriteRaw(dir / "long.binary", good + "x");
  CHECK_THROWS_WITH(ReadMerlBinary(dir / "long.binary"), Catch::Contains("trailing"));

  CHECK_THROWS_AS(ReadMerlBinary(dir / "missing.binary"), UserError);
}
