// Validation views (issue 8; Yu et al. Fig. 5): light/view pairs captured like the sample's but
// not used for the reconstruction. The map predicts what each should have shown; the capture
// says what it did show. Both are compared in the reference view's pixels as BRDF values times
// cos(theta_i) (radiance per unit irradiance at normal incidence), each pixel with the light and
// view directions it really had in that view (its correspondence map).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "acq/capture_sampling.h"
#include "acq/correspondence_source.h"
#include "acq/map_render.h"
#include "brdf/basis_rows.h"
#include "io/svbrdf_map.h"

namespace acq {

struct ValidationResult {
  std::string name;
  long pixels = 0;             // compared: valid in the map, usable in the capture
  double relative_rms = 0;     // ||predicted - captured|| / ||captured|| over those pixels
  double median_relative = 0;  // median over those pixels of |predicted - captured| / captured
  // Median over those pixels of CIEDE2000 between pi x predicted and pi x captured as linear
  // Rec. 709 reflectances (a white Lambertian lit along its normal is 1); a mono camera's grey
  // differs in lightness only.
  double median_delta_e2000 = 0;
  // The pixel whose squared error is largest and its share of the view's: relative_rms is an
  // RMS, and one pixel can carry most of it (a normal tilted a degree or two on a mirror-like
  // ink puts a view's half-vector on its peak: docs/reconstruction.md, "Normals").
  int worst_x = -1, worst_y = -1;
  double worst_share = 0;
  RgbImage predicted, captured;  // rho cos(theta_i), reference pixels; 0 where not compared
};

// What a validation view showed, in reference-view pixels: the capture as rho cos(theta_i),
// and each pixel's true light and camera directions (sample frame); any model of the sample
// (the map, the analytic maps fitted to it) is compared with it. Kept beside the session's
// renders (renders/validation_NNN.exr) so that a model made later is checked on the same data.
struct ValidationData {
  std::string name;
  int width = 0, height = 0;
  std::vector<float> captured;         // 3 a pixel
  std::vector<float> light, camera;    // unit vectors, 3 a pixel
  std::vector<std::uint8_t> compared;  // 1: valid in the map and all three channels usable
  // Where the capture was read in the view's image: a model's prediction is compared sampled
  // the same way (capture_sampling.h). Empty: at the pixels' own points.
  CapturePositions positions;
};

// A model's BRDF (1/sr, R G B) at reference pixel (x, y) for directions in the sample frame.
using PixelBrdf = std::function<std::array<double, 3>(int x, int y, const Eigen::Vector3d& in,
                                                      const Eigen::Vector3d& out)>;
PixelBrdf MapPixelBrdf(const SvbrdfMap& map, const BasisView& basis, RowLookup lookup);

// Throws UserError when the view's maps do not match the map's size.
ValidationData CaptureOfView(const SvbrdfMap& map, SessionView view);
// The model's prediction (rho cos(theta_i)) at each compared pixel's own point and directions;
// 0 where not compared.
RgbImage PredictAtPixels(const ValidationData& data, const PixelBrdf& brdf);
// A prediction at the pixels' own points, sampled as the capture was where the data say how
// (`positions`), against the capture. Throws std::invalid_argument when the sizes disagree.
ValidationResult Compare(const ValidationData& data, const RgbImage& at_pixels);
// The same for a model's BRDF: Compare(data, PredictAtPixels(data, brdf)).
ValidationResult Compare(const ValidationData& data, const PixelBrdf& brdf);
// The relative RMS of a comparison over the compared pixels of each label (labels[pixel] in
// [0, count), row-major; negative: none), e.g. per true material in simulation; 0 for a label
// with no compared pixel. Throws std::invalid_argument when the sizes disagree.
std::vector<double> RelativeRmsByLabel(const ValidationResult& result,
                                       const std::vector<int>& labels, std::size_t count);
ValidationResult CompareWithCapture(const SvbrdfMap& map, const BasisView& basis, SessionView view,
                                    RowLookup lookup);

// The planes captured.{R,G,B}, light.{x,y,z}, camera.{x,y,z}, compared and, where known, the
// capture's positions view.{x,y}; the name as an attribute. Reading names the file and what is
// missing when it is not such a file. With `predicted` (a comparison's, the same size), the model's
// prediction goes beside the capture as predicted.R/G/B (0 where not compared): a reader can find
// the pixels a view's error comes from. Reading ignores it.
void WriteValidationData(const ValidationData& data, const std::string& path,
                         const RgbImage* predicted = nullptr);
ValidationData ReadValidationData(const std::string& path);

}  // namespace acq
