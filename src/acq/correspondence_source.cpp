#include "acq/correspondence_source.h"

#include <algorithm>

#include <cmath>
#include <limits>

#include "brdf/radiometry.h"
#include "core/error.h"

namespace acq {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Bilinear sample at (x, y) in mrcal's convention (pixel centres at integers); NaN off the
// image or where any of the four pixels is unusable.
float Sample(const ViewImage& im, double x, double y) {
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= im.width || y0 + 1 >= im.height) return kNaN;
  const double fx = x - x0, fy = y - y0;
  const std::size_t i = std::size_t(y0) * std::size_t(im.width) + std::size_t(x0);
  const std::size_t w = std::size_t(im.width);
  if (const std::uint8_t* u = im.flags(); u && (u[i] || u[i + 1] || u[i + w] || u[i + w + 1]))
    return kNaN;
  const float* r = im.pixels();
  return float((1 - fy) * ((1 - fx) * r[i] + fx * r[i + 1]) +
               fy * ((1 - fx) * r[i + w] + fx * r[i + w + 1]));
}

void CheckImage(const ViewImage& im, const std::string& what) {
  // From the image's offset on, its buffer must hold its pixels (a shared buffer holds more).
  const std::size_t values = im.radiance && im.radiance->size() >= im.offset
                                 ? std::min(im.radiance->size() - im.offset,
                                            std::size_t(im.width) * std::size_t(im.height))
                                 : 0;
  if (values != std::size_t(im.width) * std::size_t(im.height))
    throw UserError(what, "image of " + std::to_string(im.width) + "x" + std::to_string(im.height) +
                              " has " + std::to_string(values) + " values");
  if (im.flags() && im.unusable->size() != values)
    throw UserError(what, "flags do not match the image's size");
}

// The planes of a view's correspondence map (calib/correspondence.h), looked up once.
struct MapPlanes {
  explicit MapPlanes(const SessionView& view)
      : x(Get(view, "x")),
        y(Get(view, "y")),
        visible(Get(view, "visible")),
        sx(Get(view, "sample.x")),
        sy(Get(view, "sample.y")),
        ix(Get(view, "wi.x")),
        iy(Get(view, "wi.y")),
        iz(Get(view, "wi.z")),
        ox(Get(view, "wo.x")),
        oy(Get(view, "wo.y")),
        oz(Get(view, "wo.z")),
        light(view.light_in_sample_mm) {}
  const std::vector<float>&x, &y, &visible, &sx, &sy, &ix, &iy, &iz, &ox, &oy, &oz;
  Eigen::Vector3d light;  // the view's light, sample frame

  // The point is seen in the view and lands on its image.
  bool Seen(std::size_t q) const { return visible[q] > 0.5f && std::isfinite(x[q]); }
  double LightDistance2(std::size_t q) const {
    return (light - Eigen::Vector3d(sx[q], sy[q], 0)).squaredNorm();
  }
  // L_spectralon r^2 / cos(theta_i): constant over a Lambertian board under a point light.
  double BoardLevelOf(float Ls, std::size_t q) const {
    return double(Ls) * LightDistance2(q) / double(iz[q]);
  }
  // Whether a Spectralon reading at point q is the board's: at least kMinSpectralonShare of what
  // the view's light gives the board there (its level cos(theta_i) / r^2). The one rule.
  bool ReadsBoard(float Ls, double level, std::size_t q) const {
    return std::isfinite(Ls) && double(Ls) >= kMinSpectralonShare * level *
                                                  std::max(double(iz[q]), 0.0) / LightDistance2(q);
  }

 private:
  static const std::vector<float>& Get(const SessionView& view, const char* plane) {
    return view.correspondence.Plane(plane, view.name);
  }
};

// Where the view's light falls on the sample at a cosine this low, the board's reading is too
// small and too steep a function of the point to set its level.
constexpr double kLevelMinCos = 0.05;

// The view's Spectralon level per channel (MapPlanes::BoardLevelOf) at its kLevelPercentile over
// the map's seen points: a high percentile, so that a board covering as little as a fifth of the
// sample sets it (its noise, a few percent, moves the level by as much; the share allows for far
// more).
constexpr double kLevelPercentile = 0.8;
std::array<double, 3> BoardLevel(const SessionView& view, const MapPlanes& m) {
  std::array<double, 3> level{0, 0, 0};
  if (view.spectralon[0].empty()) return level;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> values;
    for (std::size_t q = 0; q < m.x.size(); ++q) {
      if (!m.Seen(q) || !(m.iz[q] > kLevelMinCos)) continue;
      const float Ls = Sample(view.spectralon[c], m.x[q], m.y[q]);
      if (Ls > 0) values.push_back(m.BoardLevelOf(Ls, q));
    }
    if (values.empty()) continue;
    const auto at = values.begin() + std::ptrdiff_t(kLevelPercentile * double(values.size() - 1));
    std::nth_element(values.begin(), at, values.end());
    level[std::size_t(c)] = *at;
  }
  return level;
}

// How many of the map's seen points of the view the Spectralon does not read its board at, in
// some channel (MapPlanes::ReadsBoard, as CorrespondenceSource::Rows applies it).
long OffBoardPoints(const SessionView& view, const MapPlanes& m,
                    const std::array<double, 3>& level) {
  if (view.spectralon[0].empty()) return 0;
  long off = 0;
  for (std::size_t q = 0; q < m.x.size(); ++q) {
    if (!m.Seen(q)) continue;
    bool any = false;
    for (int c = 0; c < 3 && !any; ++c) {
      const float Ls = Sample(view.spectralon[c], m.x[q], m.y[q]);
      any = std::isfinite(Ls) && !m.ReadsBoard(Ls, level[std::size_t(c)], q);
    }
    off += any;
  }
  return off;
}

}  // namespace

ViewImage::ViewImage(int width, int height, std::vector<float> radiance,
                     std::vector<std::uint8_t> unusable)
    : width(width),
      height(height),
      radiance(std::make_shared<const std::vector<float>>(std::move(radiance))),
      unusable(std::make_shared<const std::vector<std::uint8_t>>(std::move(unusable))) {}

ViewImage::ViewImage(int width, int height, std::shared_ptr<const std::vector<float>> planes,
                     int plane, std::shared_ptr<const std::vector<std::uint8_t>> unusable)
    : width(width),
      height(height),
      radiance(std::move(planes)),
      offset(std::size_t(plane) * std::size_t(width) * std::size_t(height)),
      unusable(std::move(unusable)) {}

CorrespondenceSource::CorrespondenceSource(std::vector<SessionView> views, double pixel_size_mm)
    : views_(std::move(views)), pixel_size_mm_(pixel_size_mm) {
  if (views_.empty()) throw UserError("reconstruction", "no views to reconstruct from");
  width_ = views_[0].correspondence.width;
  height_ = views_[0].correspondence.height;
  for (const SessionView& v : views_) {
    if (v.correspondence.width != width_ || v.correspondence.height != height_)
      throw UserError(v.name, "correspondence map of another size than the first view's",
                      "compute all maps from the same reference view");
    for (const char* plane : {"x", "y", "visible", "sample.x", "sample.y", "wi.x", "wi.y", "wi.z",
                              "wo.x", "wo.y", "wo.z"})
      v.correspondence.Plane(plane, v.name);  // throws naming the missing plane
    for (int c = 0; c < 3; ++c) {
      CheckImage(v.sample[c], v.name + " (sample image)");
      if (!v.spectralon[c].empty()) CheckImage(v.spectralon[c], v.name + " (Spectralon)");
    }
    const MapPlanes planes(v);
    board_level_.push_back(BoardLevel(v, planes));
    off_board_ += OffBoardPoints(v, planes, board_level_.back());
  }
}

std::string CorrespondenceSource::Describe() const {
  return std::to_string(views_.size()) + " views through correspondence maps (" +
         std::to_string(width_) + " x " + std::to_string(height_) + " reference pixels)";
}

PixelObservations CorrespondenceSource::Rows(int y0, int rows) {
  PixelObservations obs;
  const int nviews = int(views_.size());
  obs.Resize(rows * width_, nviews);
  obs.width = width_;
  for (int v = 0; v < nviews; ++v) {
    const SessionView& view = views_[std::size_t(v)];
    const MapPlanes m(view);
    const bool spectralon = !view.spectralon[0].empty();
    const std::array<double, 3>& level = board_level_[std::size_t(v)];
#pragma omp parallel for schedule(static)
    for (int p = 0; p < rows * width_; ++p) {
      const std::size_t q = std::size_t(y0) * std::size_t(width_) + std::size_t(p);
      const std::size_t at = obs.At(p, v);
      obs.light[at] = Eigen::Vector3f(m.ix[q], m.iy[q], m.iz[q]);
      obs.camera[at] = Eigen::Vector3f(m.ox[q], m.oy[q], m.oz[q]);
      if (!m.Seen(q)) continue;  // stays NaN: dropped
      for (int c = 0; c < 3; ++c) {
        const float L = Sample(view.sample[c], m.x[q], m.y[q]);
        if (!std::isfinite(L)) continue;
        double f;
        if (spectralon) {
          const float Ls = Sample(view.spectralon[c], m.x[q], m.y[q]);
          f = m.ReadsBoard(Ls, level[std::size_t(c)], q) ? BrdfFromSpectralon(L, Ls) : std::nan("");
        } else {
          f = BrdfFromPointLight(L, view.light_intensity, std::sqrt(m.LightDistance2(q)), m.iz[q]);
        }
        obs.rgb[3 * at + std::size_t(c)] = float(f);
      }
    }
  }
  return obs;
}

}  // namespace acq
