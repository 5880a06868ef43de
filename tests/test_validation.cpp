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
  ValidationData back = ReadValidationData(path);
  CHECK(back.captured == d.captured);
  CHECK(back.compared == d.compared);
  CHECK(back.positions.empty());  // none given: compared at the pixels' own points
  d.positions = {{10.25f, std::nanf("")}, {3.5f, std::nanf("")}};
  WriteValidationData(d, path);
  back = ReadValidationData(path);
  CHECK(back.positions.x[0] == 10.25f);
  CHECK(back.positions.y[0] == 3.5f);
  CHECK(std::isnan(back.positions.x[1]));
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

namespace {

// A view of `width` x 3 reference pixels whose row y lands at view row y + 7 and whose column x
// at view column scale x + offset: the rows exact, the columns as given.
CapturePositions ColumnsAt(int width, double scale, double offset) {
  CapturePositions p;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < width; ++x) {
      p.x.push_back(float(scale * x + offset));
      p.y.push_back(float(y + 7));
    }
  return p;
}

// Grey values, 3 a pixel, of `width` x 3 pixels: `spike` at column `at` of every row, 0 elsewhere.
std::vector<float> Spike(int width, int at, float spike) {
  std::vector<float> v(std::size_t(width) * 3 * 3, 0.0f);
  for (int y = 0; y < 3; ++y)
    for (int c = 0; c < 3; ++c)
      v[3 * (std::size_t(y) * std::size_t(width) + std::size_t(at)) + std::size_t(c)] = spike;
  return v;
}

float Column(const std::vector<float>& v, int width, int x) {
  return v[3 * (std::size_t(width) + std::size_t(x))];
}

}  // namespace

TEST_CASE("a prediction sampled as the capture was", "[validation]") {
  // A spike of 8 at column 3 of 7; the middle row read. The capture interpolates the two view
  // pixels either side of where a reference pixel lands, and each of those saw its own point:
  // - a whole view pixel off: each reference pixel is a view pixel, the prediction unchanged;
  // - half a pixel off: view pixels at reference x - 1/2 and x + 1/2, weighted 1/2 each, each
  //   read between two reference pixels: 1/4, 1/2, 1/4 of the spike;
  // - foreshortened twice (two view pixels a reference pixel) and half a pixel off: the points
  //   a quarter of a reference pixel either side: 1/8, 3/4, 1/8.
  const int w = 7;
  const std::vector<std::uint8_t> known(w * 3, 1);
  const std::vector<float> spike = Spike(w, 3, 8);
  const std::vector<float> shifted = SampleAsCaptured(w, 3, ColumnsAt(w, 1, 3), spike, known);
  for (int x = 0; x < w; ++x) CHECK(Column(shifted, w, x) == Approx(Column(spike, w, x)));
  const std::vector<float> half = SampleAsCaptured(w, 3, ColumnsAt(w, 1, 3.5), spike, known);
  CHECK(Column(half, w, 2) == Approx(2));
  CHECK(Column(half, w, 3) == Approx(4));
  CHECK(Column(half, w, 4) == Approx(2));
  CHECK(Column(half, w, 5) == Approx(0));
  const std::vector<float> fore = SampleAsCaptured(w, 3, ColumnsAt(w, 2, 3.5), spike, known);
  CHECK(Column(fore, w, 2) == Approx(1));
  CHECK(Column(fore, w, 3) == Approx(6));
  CHECK(Column(fore, w, 4) == Approx(1));
  // A pixel whose view pixels' points fall off the grid, or where it was not read, keeps its own.
  CHECK(Column(half, w, 0) == Approx(0));
  CapturePositions unread = ColumnsAt(w, 1, 3.5);
  unread.x[std::size_t(w) + 3] = std::nanf("");
  CHECK(Column(SampleAsCaptured(w, 3, unread, spike, known), w, 3) == Approx(8));
  // Only known predictions are read: a pixel beside an unknown one is read from the others.
  std::vector<std::uint8_t> some = known;
  for (int y = 0; y < 3; ++y) some[std::size_t(y * w + 2)] = 0;
  CHECK(Column(SampleAsCaptured(w, 3, ColumnsAt(w, 1, 3.5), spike, some), w, 3) ==
        Approx(0.5 * 8 + 0.5 * (0.5 * 8 + 0.5 * 0)));
  CHECK_THROWS_AS(SampleAsCaptured(w, 2, ColumnsAt(w, 1, 3), spike, known), std::invalid_argument);
}

TEST_CASE("a capture of a pixel-wide highlight is matched by its prediction sampled the same way",
          "[validation]") {
  // The sample is cells, one a reference pixel; a highlight of 10 in cell 8 of 16. The view
  // lands reference column x at view column x + 0.4, and its pixel q sees the cell under its
  // own point, q - 0.4. The capture is read as the session reads it (the two view pixels either
  // side, bilinear). The true prediction at the pixels' own points has the highlight in one
  // pixel where the capture spreads it over two (4.6 and 6.4 in columns 7 and 8); sampled as the
  // capture was, it is spread over them too (3.16, 5.68, and 3.16 in column 9: reading the
  // prediction between pixels is bilinear, the cells are not) and the error falls from 0.58 to
  // 0.31 of the capture. The check leaves room for the rounding of those figures.
  const int w = 16;
  const auto cell = [](long i) { return i == 8 ? 10.0f : 1.0f; };
  ValidationData d;
  d.name = "validation 0";
  d.width = w, d.height = 3;
  d.positions = ColumnsAt(w, 1, 0.4);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < w; ++x) {
      const double at = x + 0.4;
      const long q = long(std::floor(at));
      const double f = at - double(q);
      const float v = float((1 - f) * cell(std::lround(double(q) - 0.4)) +
                            f * cell(std::lround(double(q + 1) - 0.4)));
      d.captured.insert(d.captured.end(), {v, v, v});
      d.light.insert(d.light.end(), {0, 0, 1});
      d.camera.insert(d.camera.end(), {0, 0, 1});
      d.compared.push_back(1);
    }
  const PixelBrdf truth = [&cell](int x, int, const Eigen::Vector3d&,
                                  const Eigen::Vector3d&) -> std::array<double, 3> {
    return {cell(x), cell(x), cell(x)};
  };
  const double sampled = Compare(d, truth).relative_rms;
  ValidationData at_pixels = d;
  at_pixels.positions = {};
  const double own = Compare(at_pixels, truth).relative_rms;
  CHECK(own > 0.1);  // the capture's spread highlight against the pixel's own
  CHECK(sampled < 0.6 * own);
}
