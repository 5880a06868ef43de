#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "acq/validation.h"
#include "io/float_planes_exr.h"

using namespace acq;

TEST_CASE("a validation view's relative RMS split by label", "[validation]") {
  // Four pixels, two labels and one unlabelled: label 0 predicts twice its capture (relative
  // RMS 1), label 1 exactly (0); the unlabelled pixel and a label with no pixel count nowhere.
  ValidationResult r;
  r.predicted = {4, 1, {2, 2, 2, 4, 4, 4, 1, 1, 1, 9, 9, 9}};
  r.captured = {4, 1, {1, 1, 1, 2, 2, 2, 1, 1, 1, 1, 1, 1}};
  const std::vector<double> by = RelativeRmsByLabel(r, {0, 0, 1, -1}, 3);
  REQUIRE(by.size() == 3);
  CHECK(by[0] == Approx(1.0));
  CHECK(by[1] == 0.0);
  CHECK(by[2] == 0.0);
  CHECK_THROWS_AS(RelativeRmsByLabel(r, {0, 0, 1}, 3), std::invalid_argument);
}

TEST_CASE("a validation view's data keeps the prediction beside the capture", "[validation]") {
  // Two pixels: the capture, its directions and the prediction written, read back unchanged;
  // the prediction is in the file for a reader and the capture's reader ignores it.
  ValidationData d;
  d.name = "validation 0";
  d.width = 2, d.height = 1;
  d.captured = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
  d.light = {0, 0, 1, 0, 0, 1};
  d.camera = {0, 0.6f, 0.8f, 0, 0.6f, 0.8f};
  d.compared = {1, 0};
  const RgbImage predicted{2, 1, {0.15f, 0.25f, 0.35f, 0, 0, 0}};
  const std::string path = "test_validation_data.exr";
  WriteValidationData(d, path, &predicted);
  const FloatPlanes f = ReadFloatPlanesExr(path);
  CHECK(f.Plane("predicted.R", path)[0] == 0.15f);
  CHECK(f.Plane("predicted.B", path)[0] == 0.35f);
  CHECK(f.Plane("predicted.G", path)[1] == 0.0f);
  const ValidationData back = ReadValidationData(path);
  CHECK(back.captured == d.captured);
  CHECK(back.compared == d.compared);
  // Without a prediction (a model compared later), no such plane.
  WriteValidationData(d, path);
  CHECK(ReadFloatPlanesExr(path).planes.count("predicted.R") == 0);
  std::remove(path.c_str());
}

TEST_CASE("a validation view names the pixel that carries most of its RMS", "[validation]") {
  // Three compared pixels of a 2 x 2 view, lit along the normal; the model predicts the capture
  // exactly but for pixel (0, 1), 3 over in every channel, and pixel (1, 0), 1 over: the first
  // carries 9 / (9 + 1) of the squared error. Pixel (1, 1) is not compared (its error ignored).
  ValidationData d;
  d.name = "validation 0";
  d.width = 2, d.height = 2;
  d.captured.assign(12, 1.0f);
  d.light = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  d.camera = d.light;
  d.compared = {1, 1, 1, 0};
  const ValidationResult r = Compare(
      d, [](int x, int y, const Eigen::Vector3d&, const Eigen::Vector3d&) -> std::array<double, 3> {
        const double v = x == 0 && y == 1 ? 4 : x == 1 && y == 0 ? 2 : x == 1 && y == 1 ? 100 : 1;
        return {v, v, v};
      });
  CHECK(r.pixels == 3);
  CHECK(r.worst_x == 0);
  CHECK(r.worst_y == 1);
  CHECK(r.worst_share == Approx(0.9));
  CHECK(r.relative_rms == Approx(std::sqrt(30.0 / 9.0)));
}
