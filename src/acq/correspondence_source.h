// Observations of a real (or simulated) session (issues 4 and 7): for each reference-view pixel
// and each view, the view's HDR radiance sampled where the pixel's sample point lands (the
// correspondence map of that view, calib/correspondence.h), turned into a BRDF value with the
// radiometric calibration, with the pixel's own light and view directions from the map.
//
// Radiometry (brdf/radiometry.h): with a Spectralon capture of the view (same pose, same light),
// f = R L / (pi L_spectralon) sampled at the same image position, so the light need not be known;
// without one, the point-light model f = L r^2 / (I cos(theta_i)) with the light's intensity I
// and its distance r from the pixel's sample point. An observation is dropped for that pixel
// (NaN, never a number) when the point is not visible in the view, its position falls off the
// image, or any of the four pixels it is interpolated from was saturated or in the noise floor
// in every frame of the bracket; and, with a Spectralon, where the board reads under
// kMinSpectralonShare of what the view's light gives it there (off the board's edge, a shadow,
// dust): the quotient there is not the sample's BRDF (a map's edge row read 80 times too bright
// in one channel, and carried two thirds of a validation view's error).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "brdf/pixel_solver.h"
#include "io/float_planes_exr.h"

namespace acq {

// One colour channel of one view: an HDR image (linear, any consistent unit) and its flags.
// The pixels are shared and read-only: a mono camera's three channels are one image, and a view
// is moved or copied without its pixels (a 2048 x 2048 channel is 20 MB).
struct ViewImage {
  ViewImage() = default;
  ViewImage(int width, int height, std::vector<float> radiance,
            std::vector<std::uint8_t> unusable = {});
  // Plane `plane` of a buffer of planes one after the other (a colour image's R, G and B share
  // one buffer: no copy).
  ViewImage(int width, int height, std::shared_ptr<const std::vector<float>> planes, int plane,
            std::shared_ptr<const std::vector<std::uint8_t>> unusable);
  bool empty() const { return !radiance || radiance->empty(); }
  const float* pixels() const { return radiance->data() + offset; }
  // The flags, or null where every pixel is usable.
  const std::uint8_t* flags() const {
    return unusable && !unusable->empty() ? unusable->data() : nullptr;
  }

  int width = 0, height = 0;
  std::shared_ptr<const std::vector<float>> radiance;  // this image's pixels from `offset` on
  std::size_t offset = 0;
  // Non-zero: saturated or dark in every frame; null or empty: every pixel usable.
  std::shared_ptr<const std::vector<std::uint8_t>> unusable;
};

struct SessionView {
  FloatPlanes correspondence;           // the planes of calib/correspondence.h
  std::array<ViewImage, 3> sample;      // R, G, B (a mono camera: the same image thrice)
  std::array<ViewImage, 3> spectralon;  // empty radiance: use the point-light model
  Eigen::Vector3d light_in_sample_mm = Eigen::Vector3d(0, 0, 1000);
  double light_intensity = 1;  // radiance units x mm^2, for the point-light model
  std::string name;            // for messages ("view 7", a file name)
  int pose = -1;               // its pose in the session's step (files are named by it), or -1
};

// A Spectralon reading under this share of the view's light at the point (the board's level of
// L_spectralon r^2 / cos(theta_i) over the points it images, times cos(theta_i) / r^2) is not
// the board. The board is Lambertian and the light a point: over a sample at 1 m the reading
// departs from that model by the light's beam and the noise, a few percent, never a half.
inline constexpr double kMinSpectralonShare = 0.5;

class CorrespondenceSource : public ObservationSource {
 public:
  // Throws UserError naming the view when maps differ in size or lack a plane, or images are
  // inconsistent.
  CorrespondenceSource(std::vector<SessionView> views, double pixel_size_mm);

  int Width() const override { return width_; }
  int Height() const override { return height_; }
  double PixelSizeMm() const override { return pixel_size_mm_; }
  std::string Describe() const override;
  PixelObservations Rows(int y0, int rows) override;
  // Observations (a pixel in a view, visible there) that Rows drops in some channel because the
  // Spectralon does not read its board at the point (kMinSpectralonShare); counted once, here.
  long OffBoardObservations() const { return off_board_; }

 private:
  std::vector<SessionView> views_;
  // Per view and channel, the Spectralon's level of L r^2 / cos(theta_i) (0: no Spectralon).
  std::vector<std::array<double, 3>> board_level_;
  long off_board_ = 0;
  int width_ = 0, height_ = 0;
  double pixel_size_mm_ = 0;
};

}  // namespace acq
