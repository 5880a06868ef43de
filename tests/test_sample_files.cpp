// The files a user describes a simulated sample with are checked before anything is built from
// them: a value that is not what the file's role says (a fractional label, a colour image read as
// grey, a height that is not finite) is an error naming the file and the pixel, never a sample
// silently made of something else.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "io/float_planes_exr.h"
#include "sim/relief.h"
#include "sim/sample_files.h"
#include "sim/sample_layouts.h"
#include "test_helpers.h"

using namespace acq;

TEST_CASE("a label that is not a whole number is refused, naming the pixel", "[samples]") {
  test::TempDir dir;
  FloatPlanes labels;
  labels.width = 3, labels.height = 2;
  labels.planes["label"] = {0, 1, 1, 0, 0.5f, 0};  // a weight image given as labels
  WriteFloatPlanesExr(dir / "labels.exr", labels);
  CHECK_THROWS_WITH(sim::ReadSampleLabels(dir / "labels.exr", 2, 10.0),
                    Catch::Contains("labels.exr") && Catch::Contains("pixel (1, 1) has label 0.5"));
  labels.planes["label"][4] = std::numeric_limits<float>::quiet_NaN();
  WriteFloatPlanesExr(dir / "labels.exr", labels);
  CHECK_THROWS_WITH(sim::ReadSampleLabels(dir / "labels.exr", 2, 10.0),
                    Catch::Contains("pixel (1, 1) has label nan"));
  // Mended, the file is read.
  labels.planes["label"][4] = 1;
  WriteFloatPlanesExr(dir / "labels.exr", labels);
  CHECK(sim::ReadSampleLabels(dir / "labels.exr", 2, 10.0).layout.label[4] == 1);
}

TEST_CASE("a colour PNG is refused as a label image or a height map; grey saved as RGB is read",
          "[samples]") {
  test::TempDir dir;
  cv::Mat colour(4, 4, CV_8UC3, cv::Scalar(0, 0, 0));
  colour.at<cv::Vec3b>(1, 2) = {0, 0, 1};  // one pixel's red differs: a colour-coded label
  cv::imwrite(dir / "colour.png", colour);
  CHECK_THROWS_WITH(sim::ReadSampleLabels(dir / "colour.png", 2, 10.0),
                    Catch::Contains("colour.png") && Catch::Contains("label image is in colour"));
  CHECK_THROWS_WITH(sim::ReadHeightMap(dir / "colour.png", 4, 4, 8.0),
                    Catch::Contains("height map is in colour"));

  cv::Mat grey_rgba(4, 4, CV_8UC4, cv::Scalar(0, 0, 0, 255));
  grey_rgba.at<cv::Vec4b>(1, 2) = {1, 1, 1, 128};
  cv::imwrite(dir / "grey.png", grey_rgba);
  const sim::MixedSample s = sim::ReadSampleLabels(dir / "grey.png", 2, 10.0);
  CHECK(s.layout.label[1 * 4 + 2] == 1);
  CHECK(s.layout.label[0] == 0);
  const std::vector<float> h = sim::ReadHeightMap(dir / "grey.png", 4, 4, 255.0);
  CHECK(h[1 * 4 + 2] == Approx(1.0));  // full scale 255 pixels: value 1 is one pixel high

  cv::imwrite(dir / "float.tiff", cv::Mat(4, 4, CV_32F, cv::Scalar(0)));
  CHECK_THROWS_WITH(sim::ReadGreyImage(dir / "float.tiff", "height map", "give a PNG"),
                    Catch::Contains("neither 8- nor 16-bit"));
}

TEST_CASE("a height that is not finite is refused, naming the pixel", "[samples]") {
  test::TempDir dir;
  FloatPlanes planes;
  planes.width = 4, planes.height = 2;
  planes.planes["height"].assign(8, 0.0f);
  planes.planes["height"][6] = std::numeric_limits<float>::infinity();
  WriteFloatPlanesExr(dir / "height.exr", planes);
  CHECK_THROWS_WITH(sim::ReadHeightMap(dir / "height.exr", 4, 2, 8.0),
                    Catch::Contains("height.exr") && Catch::Contains("pixel (2, 1)") &&
                        Catch::Contains("not finite"));
}
