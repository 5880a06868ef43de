#include "sim/sample_renderer.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/colour.h"
#include "core/error.h"
#include "core/facet_frame.h"

namespace acq::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The Lambertian albedo, or the SVBRDF's value, of the sample at `point`.
std::array<double, 3> Brdf(const RenderScene& scene, const Eigen::Vector2d& point,
                           const DirectionPair& d) {
  const double half = scene.sample_size_mm / 2;
  auto lambert = [](double albedo) {
    const double f = albedo / kPi;
    return std::array<double, 3>{f, f, f};
  };
  switch (scene.kind) {
    case RenderScene::Kind::kCard: {
      const int label = scene.card.LabelAt(point);
      if (label < 0) break;
      // A fit's slightly negative value is none (as the synthetic observations take it).
      const GroundTruth& material = scene.materials.at(std::size_t(label));
      std::array<double, 3> f;
      if (scene.card.normal.empty()) {  // flat: no turn per point on the renderer's hot path
        f = material.Value(d);
        for (double& v : f) v = std::max(v, 0.0);
        return f;
      }
      // A tilted facet (relief): dark where it turns away from the light or the camera.
      return material.ValueOnFacet(scene.card.NormalAt(point), d);
    }
    case RenderScene::Kind::kChessboard: {
      const double s = scene.board.spacing_mm;
      const double w = (scene.board.width_n + 1) * s, h = (scene.board.height_n + 1) * s;
      const double u = point.x() + w / 2, v = point.y() + h / 2;
      // The printed squares inside a white margin one square wide (detectors need it).
      if (u < -s || v < -s || u >= w + s || v >= h + s) break;
      if (u < 0 || v < 0 || u >= w || v >= h) return lambert(scene.board_white);
      const int i = int(u / s), j = int(v / s);
      return lambert((i + j) % 2 ? scene.board_white : scene.board_black);
    }
    case RenderScene::Kind::kSpectralon:
      if (std::abs(point.x()) >= half || std::abs(point.y()) >= half) break;
      return lambert(scene.spectralon_albedo);
    case RenderScene::Kind::kChart: {
      if (scene.chart_cover && scene.chart_cover->contains(point))
        return lambert(scene.chart_cover_albedo);
      if (!scene.chart.OnChart(point)) break;
      const std::optional<int> patch = scene.chart.PatchAt(point);
      if (!patch) return lambert(scene.chart_body_albedo);
      std::array<double, 3> f = ColorCheckerClassic()[std::size_t(*patch)].rgb;
      for (double& v : f) v /= kPi;
      return f;
    }
  }
  return lambert(scene.background_albedo);
}

}  // namespace

std::vector<float> RadianceImage::Channel(int channel) const {
  std::vector<float> out(std::size_t(width) * std::size_t(height));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const float* p = &rgb[3 * i];
    out[i] = channel < 0 ? float(kRec709Luminance[0] * p[0] + kRec709Luminance[1] * p[1] +
                                 kRec709Luminance[2] * p[2])
                         : p[channel];
  }
  return out;
}

std::array<double, 3> RadianceAt(const RenderScene& scene, const Eigen::Vector2d& point,
                                 const Eigen::Vector3d& eye, const PointLight& light) {
  const Eigen::Vector3d p(point.x(), point.y(), 0);
  const Eigen::Vector3d to_light = light.position_mm - p, to_eye = eye - p;
  if (to_light.z() <= 0 || to_eye.z() <= 0) return {0, 0, 0};  // below the horizon
  const double d2 = to_light.squaredNorm();
  const DirectionPair d{to_light.normalized(), to_eye.normalized()};
  const double irradiance = light.intensity * d.in.z() / d2;
  std::array<double, 3> f = Brdf(scene, point, d);
  for (int c = 0; c < 3; ++c) f[c] *= irradiance * light.rgb[c];
  return f;
}

RadianceImage RenderRadiance(const RenderScene& scene, const calib::CameraModel& camera,
                             const calib::Pose& cam_from_sample, const PointLight& light,
                             int ray_grid_step_px) {
  if (ray_grid_step_px < 1) throw UserError("renderer", "the ray grid step must be >= 1 pixel");
  const int w = camera.width(), h = camera.height(), step = ray_grid_step_px;
  // A chessboard is rendered in its own frame, where it is the z = 0 plane like a sample.
  const bool board = scene.kind == RenderScene::Kind::kChessboard;
  const calib::Pose plane_from_cam =
      board ? scene.sample_from_chessboard.Inverse().Compose(cam_from_sample.Inverse())
            : cam_from_sample.Inverse();
  PointLight plane_light = light;
  if (board) plane_light.position_mm = scene.sample_from_chessboard.Inverse() * light.position_mm;
  const Eigen::Matrix3d R = plane_from_cam.R();
  const Eigen::Vector3d eye = plane_from_cam.t;
  // Rays (in the plane's frame) on a coarse grid: mrcal's unprojection is iterative, and the
  // rays vary smoothly across the imager, so bilinear interpolation between grid rays is exact
  // to far below a pixel for any lens a sample is shot through.
  const int gw = (w - 1) / step + 2, gh = (h - 1) / step + 2;
  std::vector<Eigen::Vector3d> grid(std::size_t(gw) * std::size_t(gh));
  for (int j = 0; j < gh; ++j)
    for (int i = 0; i < gw; ++i)
      grid[std::size_t(j) * gw + i] =
          R *
          camera.Unproject(Eigen::Vector2d(std::min(i * step, w - 1), std::min(j * step, h - 1)));
  RadianceImage out{w, h, std::vector<float>(std::size_t(w) * std::size_t(h) * 3, 0.f)};
  // The ray through imager point (px, py), pixel centres at integers, bilinear between grid rays.
  const auto ray_at = [&](double px, double py) -> Eigen::Vector3d {
    px = std::clamp(px, 0.0, double(w - 1));
    py = std::clamp(py, 0.0, double(h - 1));
    const int i = std::min(int(px) / step, gw - 2), j = std::min(int(py) / step, gh - 2);
    const double fx = (px - i * step) / step, fy = (py - j * step) / step;
    return (1 - fy) *
               ((1 - fx) * grid[std::size_t(j) * gw + i] + fx * grid[std::size_t(j) * gw + i + 1]) +
           fy * ((1 - fx) * grid[std::size_t(j + 1) * gw + i] +
                 fx * grid[std::size_t(j + 1) * gw + i + 1]);
  };
  const int samples = std::max(scene.pixel_samples, 1);
  const double weight = 1.0 / (samples * samples);  // each point's share of its pixel
#pragma omp parallel for schedule(dynamic, 8)
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::array<double, 3> sum{};
      for (int sy = 0; sy < samples; ++sy)
        for (int sx = 0; sx < samples; ++sx) {
          const Eigen::Vector3d ray =
              ray_at(x + (sx + 0.5) / samples - 0.5, y + (sy + 0.5) / samples - 0.5);
          if (ray.z() >= 0) continue;  // never meets the plane below the camera
          const double t = -eye.z() / ray.z();
          const Eigen::Vector3d p = eye + t * ray;
          const std::array<double, 3> L = RadianceAt(scene, p.head<2>(), eye, plane_light);
          for (int c = 0; c < 3; ++c) sum[c] += L[c] * weight;
        }
      float* o = &out.rgb[3 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
      for (int c = 0; c < 3; ++c) o[c] = float(sum[c]);
    }
  }
  return out;
}

double SensorModel::CountsPerElectron(int max_dn, double gain_db) const {
  return max_dn / full_well_e * std::pow(10.0, gain_db / 20);
}

std::vector<std::uint16_t> Expose(const std::vector<float>& radiance, double exposure_us,
                                  double gain_db, int max_dn, const SensorModel& sensor,
                                  std::uint64_t seed) {
  const double dn_per_e = sensor.CountsPerElectron(max_dn, gain_db);
  std::vector<std::uint16_t> out(radiance.size());
  const int blocks = 64;  // independent seeded streams, so threads give the same frame
#pragma omp parallel for
  for (int b = 0; b < blocks; ++b) {
    std::mt19937_64 rng(seed * 1000003u + std::uint64_t(b));
    std::normal_distribution<double> read(0, sensor.read_noise_e);
    const std::size_t begin = radiance.size() * std::size_t(b) / blocks;
    const std::size_t end = radiance.size() * std::size_t(b + 1) / blocks;
    for (std::size_t i = begin; i < end; ++i) {
      double e = std::max(0.0, double(radiance[i]) * exposure_us * sensor.quantum_scale);
      if (sensor.noise) {
        // Poisson shot noise; its normal approximation beyond 1000 electrons (exact enough,
        // and an order of magnitude faster).
        if (e < 1000) {
          std::poisson_distribution<long> shot(e);
          e = double(shot(rng));
        } else {
          e += std::sqrt(e) * std::normal_distribution<double>(0, 1)(rng);
        }
        e += read(rng);
      }
      e = std::min(e, sensor.full_well_e);
      const double dn = std::round(e * dn_per_e + sensor.black_level_dn);
      out[i] = std::uint16_t(std::clamp(dn, 0.0, double(max_dn)));
    }
  }
  return out;
}

}  // namespace acq::sim
