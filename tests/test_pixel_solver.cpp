#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "acq/correspondence_source.h"
#include "acq/height_from_normals.h"
#include "acq/map_render.h"
#include "acq/reconstruction_job.h"
#include "brdf/basis_rows.h"
#include "brdf/direction_optimizer.h"
#include "brdf/evaluation.h"
#include "brdf/fov_evaluation.h"
#include "brdf/log_mapping.h"
#include "brdf/normal_search.h"
#include "brdf/pixel_solver.h"
#include "brdf/pooled_solver.h"
#include "calib/correspondence.h"
#include "calib/synthetic_board.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/facet_frame.h"
#include "core/pixel_footprint.h"
#include "io/float_planes_exr.h"
#include "issue_split.h"
#include "sim/relief.h"
#include "sim/sample_layouts.h"
#include "sim/sim_gige_camera.h"
#include "sim/synthetic_svbrdf.h"
#include "test_helpers.h"

using namespace acq;

namespace {

// The issue-2 split's basis and four of its held-out materials as the card's inks.
struct Fixture {
  BasisData basis;
  std::vector<std::string> names = {"white-paint", "brass", "black-fabric", "pink-jasper"};
  std::vector<NeuralBrdf> networks;
  std::vector<MerlBrdf> tables;
  std::vector<sim::GroundTruth> continuous, tabulated;  // network / nearest-bin table
  std::vector<Direction> directions;
  std::vector<ArmAngles> views;
};

const Fixture& Data() {
  static const Fixture f = [] {
    Fixture d;
    d.basis = test::IssueBasis(test::IssueSplit());
    for (const auto& n : d.names) {
      const std::string path = test::DataPath("nbrdf/merl/" + n + ".h5");
      d.networks.push_back(NeuralBrdf::Load(path));
      d.tables.push_back(d.networks.back().Tabulate());
    }
    for (std::size_t i = 0; i < d.names.size(); ++i) {
      d.continuous.push_back({&d.networks[i], nullptr});
      d.tabulated.push_back({nullptr, &d.tables[i]});
    }
    d.directions = ReadDirectionsTsv(test::DataPath("directions/seed_directions_20.tsv"));
    for (const auto& dir : d.directions) d.views.push_back(ArmAnglesFor(dir.angles));
    return d;
  }();
  return f;
}

// Median over pixels and channels of the grid log-space RMSE of each pixel's reconstruction
// against its material's truth.
double MedianPixelError(const sim::SyntheticSvbrdf& scene, const PixelSolution& s,
                        const HeldOutSet& truth, bool valid_only = false) {
  std::vector<double> errors;
  const int k = s.components;
  for (std::size_t p = 0; p < scene.label.size(); ++p) {
    if (valid_only && !s.valid[p]) continue;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Map<const Eigen::VectorXf> coeff(&s.coefficients[(p * 3 + c) * k], k);
      errors.push_back(truth.LogRmse(scene.label[p] * 3 + c, coeff.cast<double>()));
    }
  }
  return Median(errors);
}

// Per-pixel rows unless a test says otherwise: the tests compare exact quantities.
PixelSolveOptions PerPixel() {
  PixelSolveOptions o;
  o.row_tile = 1;
  return o;
}

PixelSolution Solve(const sim::SyntheticSvbrdf& scene, const std::vector<sim::GroundTruth>& truth,
                    const sim::ObservationOptions& o, const PixelSolveOptions& solve) {
  const PixelObservations obs =
      sim::SyntheticObservations(scene, truth, Data().views, o, 0, int(scene.label.size()));
  PixelSolution s;
  s.Resize(obs.pixels, solve.components);
  SolvePixels(Data().basis.View(), obs, solve, &s);
  return s;
}

}  // namespace

TEST_CASE("a vanishing field of view reproduces the homogeneous reconstruction",
          "[pixel][accuracy]") {
  // Views at bin centres and a sample of size 0: every pixel sees the bin centres, where the
  // network's value is the tabulated one (float32 batch vs single: ~1e-6), so each pixel's
  // error equals the homogeneous result for its material to rounding (1e-4: float32 rows and
  // coefficients). Even a micrometre of sample moves the theta_h = 0 directions' phi_d by
  // tenths of a degree, since phi_d is undefined at theta_h = 0.
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(8, 8, 0.0, 4, 1);
  std::vector<Direction> centres;
  std::vector<ArmAngles> views;
  for (std::size_t b : BinsOf(d.directions)) {
    centres.push_back({merl::BinCentre(merl::BinFromFlat(b)), "centre"});
    views.push_back(ArmAnglesFor(centres.back().angles));
  }
  const PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, views, {}, 0, int(scene.label.size()));
  PixelSolveOptions solve = PerPixel();
  PixelSolution s;
  s.Resize(obs.pixels, solve.components);
  SolvePixels(d.basis.View(), obs, solve, &s);
  RidgeOptions ridge;
  for (std::size_t p = 0; p < scene.label.size(); ++p) {
    const int m = scene.label[p];
    const auto homogeneous =
        EvaluateHomogeneous(d.basis.View(), d.tables[m], BinsOf(centres), ridge);
    for (int c = 0; c < 3; ++c) {
      const Eigen::Map<const Eigen::VectorXf> coeff(&s.coefficients[(p * 3 + c) * 20], 20);
      REQUIRE(truth.LogRmse(m * 3 + c, coeff.cast<double>()) ==
              Approx(homogeneous[c].log_rmse).epsilon(1e-4));
    }
    REQUIRE(s.valid[p]);
    REQUIRE(s.observations[p] == 20);
  }
}

TEST_CASE("per-pixel near field equals the closed-form field-of-view evaluation",
          "[pixel][accuracy]") {
  // A uniform 10 x 10 pixel sample of each material sees exactly the evaluator's 10 x 10
  // positions; with the table as ground truth both read the same bins, so the per-pixel engine
  // (directions per pixel, rows per pixel, cos weight at the true directions) must reproduce the
  // evaluator's position-averaged error but for one deliberate difference: the engine maps each
  // observation with the cos weight of its true directions, the evaluator with its bin centre's,
  // and cos(theta_i) cos(theta_o) moves by a few percent within a bin. Measured: 0.4% at most;
  // 1% allows that and nothing more (a wrong row or direction costs tens of percent).
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  for (double fov_deg : {4.0, 10.0}) {
    FovEvalOptions fo;
    fo.geometry.sample_size_mm = NearFieldGeometry::SampleSizeForFov(DegToRad(fov_deg), 1000);
    const FovResult evaluated = EvaluateOverFov(truth, d.directions, fo);
    for (int m = 0; m < 4; ++m) {
      sim::SyntheticSvbrdf scene = sim::MakeCardLayout(10, 10, fo.geometry.sample_size_mm, 1, 1);
      std::fill(scene.label.begin(), scene.label.end(), std::uint8_t(m));
      const PixelSolution s = Solve(scene, d.tabulated, {}, PerPixel());
      for (int c = 0; c < 3; ++c) {
        double mean = 0;
        for (int p = 0; p < 100; ++p) {
          const Eigen::Map<const Eigen::VectorXf> coeff(&s.coefficients[(p * 3 + c) * 20], 20);
          mean += truth.LogRmse(m * 3 + c, coeff.cast<double>()) / 100;
        }
        INFO(fov_deg << " deg, " << d.names[m] << " channel " << c);
        CHECK(mean == Approx(evaluated.channel_log_rmse[m * 3 + c]).epsilon(1e-2));
      }
    }
  }
}

TEST_CASE("a printed card at 10 degrees: ignoring the near field is clearly worse",
          "[pixel][accuracy]") {
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(10), 1000);
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(32, 32, size, 4, 3);
  sim::ObservationOptions o;
  PixelSolveOptions nearest = PerPixel(), interpolated = PerPixel();
  interpolated.lookup = RowLookup::kInterpolated;
  const double per_pixel = MedianPixelError(scene, Solve(scene, d.continuous, o, nearest), truth);
  const double interp = MedianPixelError(scene, Solve(scene, d.continuous, o, interpolated), truth);
  o.centre_directions = true;
  const double ignoring = MedianPixelError(scene, Solve(scene, d.continuous, o, nearest), truth);
  WARN("card at 10 deg, median over pixels: per-pixel rows "
       << per_pixel << " (interpolated " << interp << "), one set of rows for all pixels "
       << ignoring);
  // Ignoring the near field mislabels every off-centre observation by up to 5 degrees; the
  // study's seed-direction figures put the cost at roughly 2x, so 1.3x is a safe floor.
  CHECK(ignoring > 1.3 * per_pixel);
}

TEST_CASE("bad observations are dropped per pixel; nothing writes NaN", "[pixel]") {
  const Fixture& d = Data();
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(6, 6, 10.0, 4, 1);
  PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, d.views, {}, 0, int(scene.label.size()));
  PixelSolveOptions solve = PerPixel();
  PixelSolution clean;
  clean.Resize(obs.pixels, 20);
  SolvePixels(d.basis.View(), obs, solve, &clean);
  // Pixel 0: a saturated highlight in view 3. Pixel 1: every view missing. Pixel 2: only 5
  // views left. Pixel 3: a NaN only in its green channel.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int c = 0; c < 3; ++c) obs.rgb[3 * obs.At(0, 3) + c] = nan;
  for (int v = 0; v < obs.views; ++v) obs.rgb[3 * obs.At(1, v)] = nan;
  for (int v = 5; v < obs.views; ++v) obs.rgb[3 * obs.At(2, v) + 2] = nan;
  obs.rgb[3 * obs.At(3, 7) + 1] = nan;
  PixelSolution s;
  s.Resize(obs.pixels, 20);
  SolvePixels(d.basis.View(), obs, solve, &s);
  CHECK(s.observations[0] == 19);
  CHECK(s.observations[1] == 0);
  CHECK_FALSE(s.valid[1]);
  CHECK(s.observations[2] == 5);
  CHECK_FALSE(s.valid[2]);  // fewer than k / 2 observations
  // Its 5 rows are independent: a finite condition number (sigma_max / sigma_min of 5 x 20).
  CHECK(std::isfinite(s.condition[2]));
  // One view fewer than k still gives a pixel its own trustworthy solve: the ridge fills in
  // the one direction no observation constrains. Its condition number is that of 19 rows.
  CHECK(std::isfinite(s.condition[0]));
  CHECK(s.observations[3] == 19);
  for (float v : s.coefficients) REQUIRE(std::isfinite(v));
  for (float v : s.residual) REQUIRE(std::isfinite(v));
  // Other pixels are untouched by their neighbours' bad views.
  for (int p = 4; p < obs.pixels; ++p)
    for (int j = 0; j < 60; ++j)
      REQUIRE(s.coefficients[p * 60 + j] == clean.coefficients[p * 60 + j]);
}

TEST_CASE("interpolated rows: at bin centres they equal the nearest rows", "[pixel]") {
  const BasisView basis = Data().basis.View();
  std::vector<float> nearest(20), interpolated(20);
  for (std::size_t b : BinsOf(RandomDirections(50, 4))) {
    const DirectionPair d = DirectionsFromRusinkiewicz(merl::BinCentre(merl::BinFromFlat(b)));
    BasisSample sn, si;
    REQUIRE(SampleBasis(basis, d.in, d.out, 20, RowLookup::kNearest, nearest.data(), &sn));
    REQUIRE(
        SampleBasis(basis, d.in, d.out, 20, RowLookup::kInterpolated, interpolated.data(), &si));
    for (int c = 0; c < 20; ++c)
      REQUIRE(interpolated[c] == Approx(nearest[c]).margin(1e-3 * std::abs(nearest[0]) + 1e-6));
    REQUIRE(si.mean == Approx(sn.mean).margin(1e-4));
  }
}

TEST_CASE("the reconstruction job streams bands into a map that equals a direct solve",
          "[pixel][map]") {
  const Fixture& d = Data();
  sim::SyntheticSource source(sim::MakeCardLayout(20, 13, 40.0, 4, 2), d.continuous, d.views, {});
  ReconstructionOptions r;
  r.method = ReconstructionMethod::kIndependent;
  r.band_rows = 5;       // 13 rows: bands of 5, 5, 3
  r.solve.row_tile = 1;  // tiles stop at band edges; per-pixel rows make the bands invisible
  r.progress = false;
  test::TempDir dir;
  const ReconstructionReport report = Reconstruct(d.basis.View(), source, r, {}, dir / "m.exr");
  CHECK(report.pixels == 260);
  CHECK(report.valid + report.no_observation + report.too_few_observations +
            report.poorly_conditioned ==
        260);
  const SvbrdfMap map = ReadSvbrdfMap(dir / "m.exr");
  CHECK(map.info.pixel_size_mm == Approx(2.0));
  const PixelSolution direct = Solve(source.scene(), d.continuous, {}, r.solve);
  for (int y = 0; y < 13; ++y)
    for (int x = 0; x < 20; ++x) {
      const int p = y * 20 + x;
      REQUIRE(map.Plane("valid", x, y) == direct.valid[p]);
      const std::vector<float> c = map.Coefficients(x, y, 2);
      for (int j = 0; j < 20; ++j) REQUIRE(c[j] == direct.coefficients[(p * 3 + 2) * 20 + j]);
    }
}

namespace {

// The source reconstructed with the default options, as a map read back from dir/m.exr.
SvbrdfMap ReconstructedMap(const BasisView& basis, sim::SyntheticSource& source,
                           const test::TempDir& dir) {
  ReconstructionOptions r;
  r.progress = false;
  Reconstruct(basis, source, r, {}, dir / "m.exr");
  return ReadSvbrdfMap(dir / "m.exr");
}

}  // namespace

TEST_CASE("using a map: view render, MERL export and spheres follow the BRDF definition",
          "[pixel][render]") {
  const Fixture& d = Data();
  const BasisView basis = d.basis.View();
  sim::SyntheticSource source(sim::MakeCardLayout(12, 10, 20.0, 4, 2), d.continuous, d.views, {});
  test::TempDir dir;
  const SvbrdfMap map = ReconstructedMap(basis, source, dir);
  const int k = map.info.components;  // the pooled map's centres may have more than 20
  std::vector<float> c;
  for (int ch = 0; ch < 3; ++ch) {
    const auto v = map.Coefficients(5, 4, ch);
    c.insert(c.end(), v.begin(), v.end());
  }
  // Export: at a bin centre, the table holds the inverse mapping of q . c + mu there.
  const MerlBrdf table = PixelAsMerl(map, basis, 5, 4);
  for (std::size_t bin : BinsOf(RandomDirections(20, 8))) {
    double x = basis.mean[bin];
    for (int j = 0; j < k; ++j) x += double(basis.Row(bin)[j]) * c[k + j];  // green
    const double want =
        std::max(UnmapBrdf(x, merl::Geometry().cos_weight[bin], basis.ref[bin]), 0.0);
    REQUIRE(table.Value(1, bin) == Approx(want).epsilon(1e-5).margin(1e-9));
  }
  // View: light 45 degrees off the normal towards the sample's +y at 1 m, camera overhead:
  // pixel (5, 4) sees rho cos(theta_i) / r^2 with its own directions. Its point: half a pixel
  // to -x of the centre and, as the map's rows run to the sample's -y (core/sample_grid.h), row 4
  // of 10 half a pixel to +y; a mirrored row rule would move it nearer the light's foot.
  NearFieldGeometry g;
  const double quarter_turn = 3.14159265358979323846 / 2;
  const ArmAngles arms{quarter_turn / 2, quarter_turn, 0, 0};
  const RgbImage view = RenderView(map, basis, arms, g, RowLookup::kNearest);
  const Eigen::Vector2d p(-0.5 * map.info.pixel_size_mm, 0.5 * map.info.pixel_size_mm);
  const DirectionPair dirs = g.DirectionsAt(DirectionsOf(arms), p);
  const auto rho = BrdfFromCoefficients(basis, c.data(), k, dirs.in, dirs.out, RowLookup::kNearest);
  const Eigen::Vector3d light = g.light_distance_mm * DirectionsOf(arms).in;
  const double r2 = (light - Eigen::Vector3d(p.x(), p.y(), 0)).squaredNorm() / 1e6;
  CHECK(view.rgb[(4 * 12 + 5) * 3] == Approx(rho[0] * dirs.in.z() / r2).epsilon(1e-5));
  // Spheres: lit inside the disc where the light is above the surface, black outside it.
  const RgbImage spheres =
      RenderSpheres(map, basis, {{5, 4}, {0, 0}}, {0, 0, 1}, 32, RowLookup::kNearest);
  CHECK(spheres.width == 64);
  CHECK(spheres.rgb[(16 * 64 + 16) * 3] > 0);  // centre of the first sphere
  CHECK(spheres.rgb[0] == 0);                  // corner, outside the disc
  CHECK_THROWS_WITH(RenderSpheres(map, basis, {{12, 0}}, {0, 0, 1}, 8, RowLookup::kNearest),
                    Catch::Contains("outside the map"));
}

TEST_CASE("a map's render averages a pixel over the camera pixel's spread where its normals vary",
          "[pixel][render][normals]") {
  const Fixture& d = Data();
  const BasisView basis = d.basis.View();
  sim::SyntheticSource source(sim::MakeCardLayout(12, 10, 20.0, 4, 2), d.continuous, d.views, {});
  test::TempDir dir;
  SvbrdfMap map = ReconstructedMap(basis, source, dir);
  const int w = map.info.width;
  const std::vector<std::string> names = SvbrdfChannelNames(map.info.components);
  const auto plane = [&](const std::string& name) -> std::vector<float>& {
    return map.planes[std::size_t(std::find(names.begin(), names.end(), name) - names.begin())];
  };
  // Rows 0-4 a ramp, the slope along x rising 0.035 (2 degrees) a pixel; rows 5-9 one tilt.
  constexpr float kRamp = 0.035f;
  const auto slope_at = [&](double x, int y) { return y < 5 ? kRamp * (x - 5.5) : 0.1; };
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3f n = NormalOfSlope(float(slope_at(x, y)), 0.02f);
      const std::size_t p = std::size_t(y) * w + x;
      plane("normal.x")[p] = n.x();
      plane("normal.y")[p] = n.y();
      plane("normal.z")[p] = n.z();
      plane("normal_status")[p] = float(NormalStatus::kEstimated);
    }
  // A brass pixel (its peak a few degrees wide) inside the ramp, lit and seen around its mirror
  // direction, where a few degrees of normal change its value most.
  const sim::SyntheticSvbrdf& scene = source.scene();
  int bx = -1, by = -1;
  for (int y = 0; y < 5 && bx < 0; ++y)
    for (int x = 1; x < w - 1 && bx < 0; ++x)
      if (scene.label[std::size_t(y) * w + x] == 1) bx = x, by = y;
  REQUIRE(bx >= 0);
  const std::vector<float> c = PixelCoefficients(map, bx, by);
  const auto point_value = [&](double slope_x, const Eigen::Vector3d& in,
                               const Eigen::Vector3d& out) {
    return SeenAsFlat(NormalOfSlope(float(slope_x), 0.02f), in, out,
                      [&](const Eigen::Vector3d& fi, const Eigen::Vector3d& fo) {
                        return BrdfFromCoefficients(basis, c.data(), map.info.components, fi, fo,
                                                    RowLookup::kNearest);
                      });
  };
  const Eigen::Vector3d in = Eigen::Vector3d(0.35, 0.1, 1).normalized();
  const Eigen::Vector3f centre = NormalOfSlope(float(slope_at(bx, by)), 0.02f);
  double point_error = 0, spread_error = 0;
  for (double offset : {-0.06, -0.03, 0.0, 0.03, 0.06}) {
    const Eigen::Vector3d mirror = 2 * in.dot(centre.cast<double>()) * centre.cast<double>() - in;
    const Eigen::Vector3d out = (mirror + Eigen::Vector3d(offset, 0, 0)).normalized();
    // What a camera pixel integrating over its whole width records: 64 points across it.
    double box = 0;
    for (int i = 0; i < 64; ++i)
      box += point_value(slope_at(bx + (i + 0.5) / 64 - 0.5, by), in, out)[1] / 64;
    map.info.pixel_spread_px = 0;  // point sampling: the pixel's own normal, as before
    const double point = MapBrdfAt(map, basis, bx, by, in, out, RowLookup::kNearest)[1];
    CHECK(point == Approx(point_value(slope_at(bx, by), in, out)[1]).epsilon(1e-5));
    map.info.pixel_spread_px = kWholePixelSpreadPx;
    const double spread = MapBrdfAt(map, basis, bx, by, in, out, RowLookup::kNearest)[1];
    point_error += std::abs(point - box);
    spread_error += std::abs(spread - box);
    // Where the normal does not vary across the pixel, its own normal's value.
    const double tilted = MapBrdfAt(map, basis, bx, 7, in, out, RowLookup::kNearest)[1];
    map.info.pixel_spread_px = 0;
    CHECK(tilted == MapBrdfAt(map, basis, bx, 7, in, out, RowLookup::kNearest)[1]);
  }
  // Brass's peak is narrower than the 2 degrees the normal turns across the pixel: at the mirror
  // direction the pixel's own normal gives 155 where the box holds 22.9 (5.6 and 20.0 at 0.03
  // off). Read in parts of 0.25 degree the mean comes within 22% at the peak and 12% beside it
  // (measured: 5% of the point render's summed departure); a tenth leaves room for the basis's
  // lookup without admitting a rule of a few fixed points (3 x 3 left 68%).
  CHECK(point_error > 0);
  CHECK(spread_error < 0.1 * point_error);
  // The map's edges take the edge's normal beyond them: finite everywhere.
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{0, 0}, {w - 1, 4}, {w - 1, 9}})
    for (double v : MapBrdfAt(map, basis, x, y, in, in, RowLookup::kNearest))
      CHECK(std::isfinite(v));
  // A ramp of 6 degrees a pixel (past kMaxTurnAcrossDeg, 4, across the box): a steep edge, whose
  // neighbours' normals are least sure; the pixel is rendered at its own normal.
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector3f n = NormalOfSlope(float(0.105 * (x - 5.5)), 0.02f);
      const std::size_t p = std::size_t(y) * w + x;
      plane("normal.x")[p] = n.x();
      plane("normal.y")[p] = n.y();
      plane("normal.z")[p] = n.z();
    }
  const auto steep = [&](double spread) {
    map.info.pixel_spread_px = spread;
    return MapBrdfAt(map, basis, bx, by, in, in, RowLookup::kNearest)[1];
  };
  CHECK(steep(kWholePixelSpreadPx) == steep(0));
}

TEST_CASE("rows shared by tiles equal per-pixel rows where the directions are the same",
          "[pixel]") {
  // A sample of size 0: every pixel sees the same directions, so sharing the tile centre's rows
  // changes nothing, also for a pixel whose own views differ (it gets its own factorisation).
  const Fixture& d = Data();
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(10, 9, 0.0, 4, 1);
  PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, d.views, {}, 0, int(scene.label.size()));
  REQUIRE(obs.width == 10);
  obs.rgb[3 * obs.At(23, 4)] = std::numeric_limits<float>::quiet_NaN();
  PixelSolveOptions per_pixel = PerPixel(), tiled;
  tiled.row_tile = 4;
  PixelSolution a, b;
  a.Resize(obs.pixels, 20);
  b.Resize(obs.pixels, 20);
  SolvePixels(d.basis.View(), obs, per_pixel, &a);
  SolvePixels(d.basis.View(), obs, tiled, &b);
  CHECK(b.observations[23] == 19);
  for (std::size_t i = 0; i < a.coefficients.size(); ++i)
    REQUIRE(b.coefficients[i] == Approx(a.coefficients[i]).margin(1e-6));
  CHECK(a.valid == b.valid);
}

// A reference camera straight above a card of n x n pixels, size_mm across, at `distance`,
// whose pixels are the card's pixels (f = d n / size).
calib::ReferenceView CardReference(int n, double size_mm, double distance) {
  calib::ReferenceView reference;
  const double f = distance * n / size_mm;
  reference.camera =
      calib::CameraModel("LENSMODEL_PINHOLE", {f, f, (n - 1) / 2.0, (n - 1) / 2.0}, n, n);
  reference.cam_from_sample = calib::CamFromSampleLookingAtCentre({0, 0, distance});
  return reference;
}

// A view's sample and Spectralon images rendered by the simulated camera's renderer at `pose`,
// and its light, into `view` (its correspondence map is the caller's).
void RenderView(const sim::RenderScene& card, const sim::RenderScene& spectralon,
                const calib::CameraModel& camera, const sim::SimView& pose, SessionView* view) {
  const sim::RadianceImage L =
      sim::RenderRadiance(card, camera, pose.cam_from_sample, pose.light, 1);
  const sim::RadianceImage Ls =
      sim::RenderRadiance(spectralon, camera, pose.cam_from_sample, pose.light, 1);
  for (int c = 0; c < 3; ++c) {
    view->sample[c] = {camera.width(), camera.height(), L.Channel(c), {}};
    view->spectralon[c] = {camera.width(), camera.height(), Ls.Channel(c), {}};
  }
  view->light_in_sample_mm = pose.light.position_mm;
  view->light_intensity = pose.light.intensity;
}

TEST_CASE("a Spectralon smaller than the sample: points off the board are dropped, not divided",
          "[pixel][session]") {
  // A 20 mm card seen by a reference camera whose pixels are its pixels, three of the set's
  // views rendered at 5 view pixels a card pixel, with a Spectralon board of 12 mm: the points
  // of the card off the board read the background there, and their quotient is no BRDF.
  const Fixture& d = Data();
  const int n = 20;
  const double size_mm = 20, distance = 1000, board_mm = 12;
  sim::RenderScene card;
  card.kind = sim::RenderScene::Kind::kCard;
  card.sample_size_mm = size_mm;
  card.card = sim::MakeCardLayout(n, n, size_mm, 4, 2);
  card.materials = d.continuous;
  sim::RenderScene spectralon = card;
  spectralon.kind = sim::RenderScene::Kind::kSpectralon;
  spectralon.sample_size_mm = board_mm;
  const calib::ReferenceView reference = CardReference(n, size_mm, distance);
  const double f_view = distance * 160 / 32.0;
  const calib::CameraModel view_camera("LENSMODEL_PINHOLE", {f_view, f_view, 79.5, 79.5}, 160, 160);
  std::vector<SessionView> views;
  for (std::size_t v : {0, 7, 14}) {
    const sim::SimView pose = sim::ViewFromArms(d.views[v], distance, distance, 1e6);
    SessionView sv;
    sv.name = "view " + std::to_string(v);
    sv.correspondence = calib::ComputeCorrespondence(
        reference, {view_camera, pose.cam_from_sample, pose.light.position_mm});
    RenderView(card, spectralon, view_camera, pose, &sv);
    views.push_back(std::move(sv));
  }
  std::vector<FloatPlanes> maps;
  for (const SessionView& v : views) maps.push_back(v.correspondence);
  CorrespondenceSource source(std::move(views), size_mm / n);
  const PixelObservations obs = source.Rows(0, n);
  // A view pixel is 0.2 mm at the sample: points further than two of them from the board's edge
  // are plainly on it or off it (bilinear sampling reaches one pixel across the edge).
  const double margin = 0.4;
  int on = 0, off = 0;
  for (int p = 0; p < obs.pixels; ++p)
    for (int v = 0; v < obs.views; ++v) {
      const FloatPlanes& m = maps[std::size_t(v)];
      if (!(m.Plane("visible", "map")[std::size_t(p)] > 0.5f)) continue;
      const double reach = std::max(std::abs(m.Plane("sample.x", "map")[std::size_t(p)]),
                                    std::abs(m.Plane("sample.y", "map")[std::size_t(p)]));
      const float value = obs.rgb[3 * obs.At(p, v)];
      if (reach > board_mm / 2 + margin) {
        INFO("pixel " << p << " view " << v << " off the board reads " << value);
        CHECK(std::isnan(value));
        ++off;
      } else if (reach < board_mm / 2 - margin) {
        CHECK(std::isfinite(value));
        ++on;
      }
    }
  // Both kinds are there to check: the board covers 36% of the card.
  CHECK(on > 300);
  CHECK(off > 300);
  // Counted for the report: each off the board (and those within the margin of its edge).
  CHECK(source.OffBoardObservations() >= off);
  CHECK(source.OffBoardObservations() < off + on);
}

TEST_CASE(
    "a session's path (rendered views, correspondence maps, Spectralon radiometry) "
    "reconstructs as well as observations taken straight from the ground truth",
    "[pixel][accuracy][session]") {
  // The card seen by a reference camera straight above it whose pixels are the card's pixels
  // (f = d W / size), then each of the 20 views rendered by the simulated camera's renderer
  // (higher resolution, pinhole, at the arms' distances), mapped back through the calibration's
  // correspondence maps, and turned into BRDF values with a Spectralon rendered in the same
  // view. The direct path gives each pixel its material's exact value at its true directions.
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const int n = 24;
  const double size_mm = 20, distance = 1000;
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(n, n, size_mm, 4, 2);
  sim::RenderScene card;
  card.kind = sim::RenderScene::Kind::kCard;
  card.sample_size_mm = size_mm;
  card.card = scene;
  card.materials = d.continuous;
  sim::RenderScene spectralon = card;
  spectralon.kind = sim::RenderScene::Kind::kSpectralon;
  spectralon.sample_size_mm = 200;

  const calib::ReferenceView reference = CardReference(n, size_mm, distance);
  // Views: 160 px across 32 mm at normal incidence, 5 view pixels per card pixel.
  const double f_view = distance * 160 / 32.0;
  const calib::CameraModel view_camera("LENSMODEL_PINHOLE", {f_view, f_view, 79.5, 79.5}, 160, 160);
  std::vector<SessionView> views;
  const test::TempDir tmp;
  for (std::size_t v = 0; v < d.views.size(); ++v) {
    const sim::SimView pose = sim::ViewFromArms(d.views[v], distance, distance, 1e6);
    calib::CalibratedView calibrated{view_camera, pose.cam_from_sample, pose.light.position_mm};
    SessionView sv;
    sv.name = "view " + std::to_string(v);
    // Through the session's file, as the reconstructor reads it (correspondence/NNN.exr).
    const std::string map_path = tmp / (std::to_string(v) + ".exr");
    WriteFloatPlanesExr(map_path, calib::ComputeCorrespondence(reference, calibrated));
    sv.correspondence = ReadFloatPlanesExr(map_path);
    RenderView(card, spectralon, view_camera, pose, &sv);
    views.push_back(std::move(sv));
  }
  // The same views without their Spectralon: the point-light model with the light's intensity.
  std::vector<SessionView> point_light_views = views;
  for (SessionView& v : point_light_views)
    for (ViewImage& im : v.spectralon) im = {};
  CorrespondenceSource point_light(std::move(point_light_views), size_mm / n);
  CorrespondenceSource source(std::move(views), size_mm / n);
  const PixelObservations obs = source.Rows(0, n);
  PixelSolveOptions solve = PerPixel();
  PixelSolution camera_path;
  camera_path.Resize(obs.pixels, solve.components);
  SolvePixels(d.basis.View(), obs, solve, &camera_path);

  // Each reference pixel's material is the card's at its sample point.
  sim::SyntheticSvbrdf seen = scene;
  const FloatPlanes map0 = calib::ComputeCorrespondence(
      reference,
      {view_camera, sim::ViewFromArms(d.views[0], distance, distance, 1e6).cam_from_sample, {}});
  for (int p = 0; p < n * n; ++p) {
    const Eigen::Vector2d point(map0.Plane("sample.x", "map")[p], map0.Plane("sample.y", "map")[p]);
    const int label = scene.LabelAt(point);  // the renderer's rule
    REQUIRE(label >= 0);
    seen.label[std::size_t(p)] = std::uint8_t(label);
  }
  sim::ObservationOptions direct_options;
  direct_options.geometry.camera_distance_mm = distance;
  direct_options.geometry.light_distance_mm = distance;
  const PixelSolution direct = Solve(scene, d.continuous, direct_options, solve);
  const double camera_error = MedianPixelError(seen, camera_path, truth);
  PixelSolution light_model;
  light_model.Resize(obs.pixels, solve.components);
  SolvePixels(d.basis.View(), point_light.Rows(0, n), solve, &light_model);
  // The renderer's light is exactly a point light: the model must agree with the Spectralon.
  CHECK(MedianPixelError(seen, light_model, truth) == Approx(camera_error).epsilon(1e-3));
  const double direct_error = MedianPixelError(scene, direct, truth);
  WARN("median log-space RMSE: session path " << camera_error << ", direct " << direct_error);
  // Every view is used by every pixel; the few pixels whose 20 directions are poorly
  // conditioned (condition number > 1e4: the near field moves them) are the same in number on
  // both paths, since conditioning depends on the directions alone.
  long camera_valid = 0, direct_valid = 0;
  for (int p = 0; p < n * n; ++p) {
    REQUIRE(camera_path.observations[std::size_t(p)] == 20);
    camera_valid += camera_path.valid[std::size_t(p)];
    direct_valid += direct.valid[std::size_t(p)];
  }
  CHECK(camera_valid == direct_valid);
  // Measured 0.3611 vs 0.3612: the renderer, the maps and the Spectralon ratio lose nothing
  // measurable. 2% allows for bilinear sampling across the card's sharp edges (a view pixel
  // straddling two inks) and nothing like a wrong direction or a misplaced pixel (tens of %).
  CHECK(camera_error == Approx(direct_error).epsilon(0.02));
}

TEST_CASE("the per-pixel condition estimate agrees with a full eigendecomposition", "[pixel]") {
  // Rows as a pixel sees them: the basis sampled at the seed's 20 directions, from pixels all
  // over a 10-degree field of view, plus subsets of 12 to 19 views (dropped observations).
  const Fixture& d = Data();
  NearFieldGeometry g;
  g.sample_size_mm = NearFieldGeometry::SampleSizeForFov(DegToRad(10), g.camera_distance_mm);
  double worst = 0, worst_warm = 0;
  ConditionEstimator warm;  // carried from matrix to matrix, as a worker does from pixel to pixel
  int warm_steps = 0, estimates = 0;
  for (const Eigen::Vector2d& p : g.Positions(4, true)) {
    for (int drop = 0; drop <= 8; drop += 4) {
      std::vector<std::vector<float>> rows;
      for (std::size_t v = 0; v + drop < d.views.size(); ++v) {
        const DirectionPair dirs = g.DirectionsAt(DirectionsOf(d.views[v]), p);
        std::vector<float> row(20);
        BasisSample sample;
        if (SampleBasis(d.basis.View(), dirs.in, dirs.out, 20, RowLookup::kNearest, row.data(),
                        &sample))
          rows.push_back(row);
      }
      Eigen::MatrixXd q(Eigen::Index(rows.size()), 20);
      for (std::size_t r = 0; r < rows.size(); ++r)
        for (int c = 0; c < 20; ++c) q(Eigen::Index(r), c) = rows[r][std::size_t(c)];
      const Eigen::MatrixXd normal = q.transpose() * q;
      const Eigen::VectorXd ev =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(normal).eigenvalues();
      const double exact = std::sqrt(ev(19) / ev(0));
      const double estimate = EstimateConditionNumber(normal);
      worst = std::max(worst, std::abs(estimate - exact) / exact);
      const double warm_estimate = warm.Estimate(normal, Eigen::LLT<Eigen::MatrixXd>(normal));
      worst_warm = std::max(worst_warm, std::abs(warm_estimate - exact) / exact);
      warm_steps += warm.last_steps();
      ++estimates;
    }
  }
  WARN("worst relative difference of the condition estimate: "
       << worst << " cold, " << worst_warm << " warm (" << double(warm_steps) / estimates
       << " steps an estimate)");
  // The validity threshold (1e4) is a round number, not a sharp physical limit: a few percent
  // near it moves a handful of pixels between valid and poorly conditioned. 5% bounds that.
  CHECK(worst < 0.05);
  CHECK(worst_warm < 0.05);
}

TEST_CASE("pixels solved in SIMD lanes equal pixels solved one at a time", "[pixel][lanes]") {
  // A 10-degree card of 37 x 29 pixels (not a multiple of the 8 or 16 lanes: the last batch is
  // partial) with 4% of its observations dropped at random, so about half the pixels keep all
  // 20 views (solved in lanes, some lanes with zero rows) and the others fall back to the
  // one-pixel path (fewer observations than k), inside the same batches.
  const Fixture& d = Data();
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(10), 1000);
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(37, 29, size, 4, 5);
  PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, d.views, {}, 0, int(scene.label.size()));
  std::mt19937 rng(7);
  std::bernoulli_distribution drop(0.04);
  for (std::size_t i = 0; i < obs.light.size(); ++i)
    if (drop(rng)) obs.rgb[3 * i + rng() % 3] = std::numeric_limits<float>::quiet_NaN();
  auto solve = [&](PixelKernel kernel, int k = 20) {
    PixelSolveOptions o = PerPixel();
    o.kernel = kernel;
    o.components = k;
    PixelSolution s;
    s.Resize(obs.pixels, o.components);
    SolvePixels(d.basis.View(), obs, o, &s);
    return s;
  };
  const PixelSolution one = solve(PixelKernel::kOnePixel);
  int full = 0;
  for (int p = 0; p < obs.pixels; ++p) full += one.observations[std::size_t(p)] == 20;
  REQUIRE(full > obs.pixels / 4);
  REQUIRE(full < obs.pixels * 3 / 4);
  for (PixelKernel kernel : {PixelKernel::kLanesDouble, PixelKernel::kLanesSingle}) {
    const bool single = kernel == PixelKernel::kLanesSingle;
    const PixelSolution lanes = solve(kernel);
    double worst_coeff = 0, worst_condition = 0, worst_residual = 0;
    int worst_condition_pixel = 0;
    std::vector<double> coeff_diff;
    int valid_differ = 0;
    for (int p = 0; p < obs.pixels; ++p) {
      const std::size_t i = std::size_t(p);
      REQUIRE(lanes.observations[i] == one.observations[i]);
      const Eigen::Map<const Eigen::VectorXf> a(&lanes.coefficients[i * 60], 60),
          b(&one.coefficients[i * 60], 60);
      REQUIRE(a.allFinite());
      const double dc = (a - b).norm() / std::max(b.norm(), 1e-6f);
      if (one.observations[i] == 20) coeff_diff.push_back(dc);  // solved in lanes
      worst_coeff = std::max(worst_coeff, dc);
      // float32 cannot resolve the smallest eigenvalue of worse conditioned rows (their normal
      // matrix's condition number, the square, nears 1 / float32's epsilon): compared below 1e3.
      const double condition_diff =
          double(std::abs(lanes.condition[i] - one.condition[i]) / one.condition[i]);
      if (std::isfinite(one.condition[i]) && (!single || one.condition[i] < 1e3) &&
          condition_diff > worst_condition)
        worst_condition = condition_diff, worst_condition_pixel = p;
      if (!std::isfinite(one.condition[i])) REQUIRE(std::isinf(lanes.condition[i]));
      worst_residual = std::max(
          worst_residual,
          double(std::abs(lanes.residual[i] - one.residual[i]) / std::max(one.residual[i], 1e-6f)));
      valid_differ += lanes.valid[i] != one.valid[i];
    }
    WARN((single ? "float32" : "float64")
         << " lanes against one pixel at a time: coefficients of the " << coeff_diff.size()
         << " pixels solved in lanes median " << Median(coeff_diff) << ", worst " << worst_coeff
         << ", over 1e-2 at "
         << std::count_if(coeff_diff.begin(), coeff_diff.end(), [](double v) { return v > 1e-2; })
         << " (relative); condition worst " << worst_condition << " (pixel "
         << worst_condition_pixel << ", " << one.observations[std::size_t(worst_condition_pixel)]
         << " rows, " << one.condition[std::size_t(worst_condition_pixel)] << " against "
         << lanes.condition[std::size_t(worst_condition_pixel)] << "); residual worst "
         << worst_residual << "; validity differs at " << valid_differ << " of " << obs.pixels);
    if (!single) {
      // The same arithmetic in another order and with fused multiply-adds: the coefficients
      // are stored as float32 (6e-8) and the ridge solve is well conditioned (eta = kDefaultEta),
      // so 1e-6 leaves room for rounding and none for a wrong row or a misplaced observation.
      CHECK(worst_coeff < 1e-6);
      CHECK(worst_residual < 1e-6);
      // Condition numbers are estimates that stop once a step moves the Rayleigh quotient by
      // under 1e-5 of it, started from different warm starts (the previous pixel, or the pixel
      // 8 to the left; a deferred pixel's from the previous deferred one). Measured: 1.2e-4
      // worst. With the iteration capped at 12 steps (before 2026-12-03) one pixel whose start
      // was nearly orthogonal to its largest eigenvector came out 16% low on one path and exact
      // on the other (pixel_solver.h, ConditionIteration); 1% allows the stop's own error and
      // not that. Validity may differ only within it of the 1e4 threshold (above).
      CHECK(worst_condition < 0.01);
    } else {
      // float32 carries 7 digits, and the ridge-regularised normal matrix loses about
      // log10(its condition number) of them: measured below; 1e-4 median and 1e-2 worst are
      // what single precision may cost without changing a map's error (the benchmark charts it).
      // A few pixels differ by more: 2 of 480 at 3.5% and 4.5% on this card since its cells
      // became square (2026-12-03). Traced: each has one view whose angles, converted in
      // float32, fall in the neighbouring MERL bin, so one of its 20 rows is another bin's.
      // So: 1e-2 for all but 1% of the pixels, and no pixel off by 10%.
      CHECK(Median(coeff_diff) < 1e-4);
      CHECK(std::count_if(coeff_diff.begin(), coeff_diff.end(),
                          [](double v) { return v > 1e-2; }) <= long(coeff_diff.size() / 100));
      CHECK(worst_coeff < 0.1);
      CHECK(worst_condition < 0.1);
    }
  }
  // k = 7, not a multiple of the products' 4 x 4 blocks (padded with zero columns): the same
  // coefficients and validity.
  const PixelSolution one7 = solve(PixelKernel::kOnePixel, 7),
                      lanes7 = solve(PixelKernel::kLanesDouble, 7);
  double worst7 = 0;
  for (int p = 0; p < obs.pixels; ++p) {
    const std::size_t i = std::size_t(p);
    const Eigen::Map<const Eigen::VectorXf> a(&lanes7.coefficients[i * 21], 21),
        b(&one7.coefficients[i * 21], 21);
    worst7 = std::max(worst7, double((a - b).norm() / std::max(b.norm(), 1e-6f)));
    CHECK(lanes7.valid[i] == one7.valid[i]);
  }
  CHECK(worst7 < 1e-6);
}

namespace {

// The pooled solve of a scene, its model fitted on every pixel of `sample_scene`.
PixelSolution SolvePooled(const sim::SyntheticSvbrdf& sample_scene,
                          const sim::SyntheticSvbrdf& scene, const sim::ObservationOptions& o,
                          PooledModel* model) {
  const Fixture& d = Data();
  const PixelSolveOptions solve = PerPixel();
  const PixelObservations sample = sim::SyntheticObservations(sample_scene, d.continuous, d.views,
                                                              o, 0, int(sample_scene.label.size()));
  *model = FitPooledModel(d.basis.View(), sample, solve, PooledOptions{});
  const PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, d.views, o, 0, int(scene.label.size()));
  PixelSolution s;
  s.Resize(obs.pixels, model->components);
  SolvePixelsPooled(d.basis.View(), obs, *model, solve, &s);
  return s;
}

// A group's centre scored over the whole grid against a material's truth, averaged over R, G, B.
double CentreError(const PooledModel& model, const PooledGroup& group, int material,
                   const HeldOutSet& truth) {
  double e = 0;
  for (int ch = 0; ch < 3; ++ch) {
    const Eigen::Map<const Eigen::VectorXf> c(&group.centre[std::size_t(ch) * model.components],
                                              group.centre_components);
    e += truth.LogRmse(material * 3 + ch, c.cast<double>()) / 3;
  }
  return e;
}

}  // namespace

TEST_CASE("the leave-one-view-out residual is each view predicted by the solve without it",
          "[pixel][lanes]") {
  // A 4-degree card of 9 x 7 pixels, k = 8 (the normal search's), one observation in 20
  // dropped; every pixel re-solved 20 times by brute force, each time without one view.
  const Fixture& d = Data();
  const int k = 8;
  const double eta = kDefaultEta;
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(4), 1000);
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(9, 7, size, 4, 3);
  PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, d.views, {}, 0, int(scene.label.size()));
  std::mt19937 rng(11);
  std::bernoulli_distribution drop(0.05);
  for (std::size_t i = 0; i < obs.light.size(); ++i)
    if (drop(rng)) obs.rgb[3 * i] = std::numeric_limits<float>::quiet_NaN();
  std::vector<double> brute(obs.pixels);
  for (int p = 0; p < obs.pixels; ++p) {
    std::vector<Eigen::VectorXd> q;
    std::vector<Eigen::Vector3d> y;
    for (int v = 0; v < obs.views; ++v) {
      const std::size_t i = obs.At(p, v);
      const float* rgb = &obs.rgb[3 * i];
      std::vector<float> row(k);
      BasisSample sample;
      if (!std::isfinite(rgb[0]) ||
          !SampleBasis(d.basis.View(), obs.light[i].cast<double>(), obs.camera[i].cast<double>(), k,
                       RowLookup::kNearest, row.data(), &sample))
        continue;
      q.push_back(Eigen::Map<Eigen::VectorXf>(row.data(), k).cast<double>());
      Eigen::Vector3d yv;
      for (int ch = 0; ch < 3; ++ch)
        yv[ch] = MapBrdf(rgb[ch], sample.cos_weight, sample.ref) - sample.mean;
      y.push_back(yv);
    }
    double sum = 0;
    for (std::size_t out = 0; out < q.size(); ++out) {
      Eigen::MatrixXd a = eta * Eigen::MatrixXd::Identity(k, k);
      Eigen::MatrixXd b = Eigen::MatrixXd::Zero(k, 3);
      for (std::size_t v = 0; v < q.size(); ++v) {
        if (v == out) continue;
        a += q[v] * q[v].transpose();
        b += q[v] * y[v].transpose();
      }
      const Eigen::MatrixXd c = a.ldlt().solve(b);
      sum += (c.transpose() * q[out] - y[out]).squaredNorm();
    }
    brute[std::size_t(p)] = std::sqrt(sum / (3.0 * double(q.size())));
  }
  for (PixelKernel kernel : {PixelKernel::kOnePixel, PixelKernel::kLanesDouble}) {
    PixelSolveOptions o = PerPixel();
    o.kernel = kernel;
    o.components = k;
    o.eta = eta;
    o.residual = ResidualKind::kLeaveOneViewOut;
    PixelSolution s;
    s.Resize(obs.pixels, k);
    SolvePixels(d.basis.View(), obs, o, &s);
    o.residual = ResidualKind::kFit;
    PixelSolution fit;
    fit.Resize(obs.pixels, k);
    SolvePixels(d.basis.View(), obs, o, &fit);
    for (int p = 0; p < obs.pixels; ++p) {
      INFO("kernel " << int(kernel) << ", pixel " << p);
      // Exact algebra both ways; the residual is stored as float32.
      CHECK(s.residual[std::size_t(p)] == Approx(brute[std::size_t(p)]).epsilon(1e-5));
      // Predicting an unseen view is never easier than fitting it.
      CHECK(s.residual[std::size_t(p)] > fit.residual[std::size_t(p)]);
    }
  }
}

TEST_CASE("pooled: at 4 degrees better than alone, at 0 degrees no worse", "[pixel][pooled]") {
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  sim::ObservationOptions o;
  o.noise_sigma = 0.02;  // seeded: the same observations every run
  for (const double fov : {0.0, 4.0}) {
    const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(fov), 1000);
    const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(48, 48, size, 4, 3);
    PooledModel model;
    const PixelSolution pooled = SolvePooled(scene, scene, o, &model);
    const double alone = MedianPixelError(scene, Solve(scene, d.continuous, o, PerPixel()), truth);
    const double with_prior = MedianPixelError(scene, pooled, truth);
    WARN("card at " << fov << " deg: median error alone " << alone << ", pooled " << with_prior
                    << "\n"
                    << model.Summary());
    // At 0 degrees the groups may be dropped (they must beat every pixel alone by 1%).
    if (fov > 0) CHECK(!model.groups.empty());
    for (float c : pooled.coefficients) REQUIRE(std::isfinite(c));
    if (fov == 0) {
      // Every pixel sees the same directions: pooling adds no direction and the centre is the
      // pixels' mean solved as one pixel; measured within 1% (docs/reconstruction.md), 3%
      // allows for this smaller card's sample.
      CHECK(with_prior < 1.03 * alone);
    } else {
      // Measured 0.35 against 0.46 on the 256 x 256 card with the optimised directions; with
      // the seed directions on 48 x 48 a tenth better is the floor.
      CHECK(with_prior < 0.9 * alone);
    }
  }
}

// "Model no more than a scene needs": at a field of view of 0 a smooth blend gives the pixels
// nothing to share (every pixel sees the same directions and no two are the same material); its
// groups' held-out gain is within the noise, so none are kept and the pooled solve is the
// independent one (to float rounding: another code path). A number of groups the user forces
// is kept.
TEST_CASE("pooled: no groups unless they beat every pixel alone", "[pixel][pooled]") {
  const Fixture& d = Data();
  const sim::MixedSample blend = sim::MakeSample(SampleKind::kBlend, 48, 48, 0.0, 2, 1);
  const std::vector<sim::GroundTruth> base = {d.continuous[0], d.continuous[1]};
  const std::vector<sim::GroundTruth> truths = blend.Truths(base);  // mixtures point into base
  sim::ObservationOptions o;
  o.noise_sigma = 0.05;  // seeded
  const PixelObservations obs = sim::SyntheticObservations(blend.layout, truths, d.views, o, 0,
                                                           int(blend.layout.label.size()));
  const PixelSolveOptions solve = PerPixel();
  const PooledModel model = FitPooledModel(d.basis.View(), obs, solve, PooledOptions{});
  INFO(model.Summary());
  REQUIRE(model.groups.empty());
  CHECK(model.dropped_held_out_rms > 0.99 * model.independent_held_out_rms);
  PixelSolution pooled, alone;
  pooled.Resize(obs.pixels, model.components);
  SolvePixelsPooled(d.basis.View(), obs, model, solve, &pooled);
  alone.Resize(obs.pixels, solve.components);
  SolvePixels(d.basis.View(), obs, solve, &alone);
  const int k = solve.components, K = model.components;
  for (int p = 0; p < obs.pixels; ++p)
    for (int ch = 0; ch < 3; ++ch)
      for (int j = 0; j < k; ++j)
        REQUIRE(pooled.coefficients[std::size_t(p) * 3 * K + std::size_t(ch) * K + j] ==
                Approx(alone.coefficients[std::size_t(p) * 3 * k + std::size_t(ch) * k + j])
                    .epsilon(1e-4)
                    .margin(1e-5));  // two code paths in float32: rounding
  PooledOptions forced;
  forced.groups = 2;
  const PooledModel two = FitPooledModel(d.basis.View(), obs, solve, forced);
  CHECK(two.groups.size() == 2);
  // At no field of view every pixel sees the same directions: a centre's rows have no more
  // independent directions than the views, and it takes no more components than that allows.
  for (const PooledGroup& g : two.groups) CHECK(g.centre_components <= std::max(k, obs.views));
}

TEST_CASE("pooled: a group's centre is weighted to the plan's directions", "[pixel][pooled]") {
  // One material at a time over a 4-degree card, one group forced: its centre fitted with every
  // pixel alike and with the design weighting, each scored over the whole grid. The plan's
  // directions were optimised for the grid's error at the sample's centre; fitting every
  // pixel's near-field directions alike spends the basis on their spread.
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const PixelSolveOptions solve = PerPixel();
  sim::ObservationOptions o;
  o.noise_sigma = 0.02;
  double sum_alike = 0, sum_weighted = 0;
  for (const double fov : {0.0, 4.0}) {
    const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(fov), 1000);
    sim::SyntheticSvbrdf scene = sim::MakeCardLayout(32, 32, size, 4, 3);
    for (int m = 0; m < int(d.names.size()); ++m) {
      std::fill(scene.label.begin(), scene.label.end(), std::uint8_t(m));
      const PixelObservations obs =
          sim::SyntheticObservations(scene, d.continuous, d.views, o, 0, int(scene.label.size()));
      PooledOptions alike, weighted;
      alike.groups = weighted.groups = 1;
      alike.design_sigma_deg = 0;
      const PooledModel a = FitPooledModel(d.basis.View(), obs, solve, alike);
      const PooledModel w = FitPooledModel(d.basis.View(), obs, solve, weighted);
      REQUIRE(a.groups.size() == 1);
      REQUIRE(w.groups.size() == 1);
      const double ea = CentreError(a, a.groups[0], m, truth);
      const double ew = CentreError(w, w.groups[0], m, truth);
      WARN(d.names[m] << " at " << fov << " deg: centre " << ea << " with every pixel alike, " << ew
                      << " weighted to the design (" << w.groups[0].effective_pixels
                      << " effective pixels of " << w.groups[0].sample_pixels << ")");
      if (fov == 0) {
        // Every pixel sees the plan's directions: the weights are all alike, over the 90% of
        // the members the centre is fitted from again (MembersExplainedBest).
        CHECK(ew == Approx(ea).epsilon(1e-9));
        const double effective = w.groups[0].effective_pixels;
        CHECK(effective == Approx(std::round(effective)).epsilon(1e-9));
        CHECK(effective >= 0.9 * w.groups[0].sample_pixels);
        CHECK(effective < w.groups[0].sample_pixels);
      } else {
        sum_alike += ea, sum_weighted += ew;
      }
    }
  }
  // On the 256 x 256 card with the optimised directions the materials' maps went 0.362 /
  // 0.239 / 0.157 / 0.155 -> 0.277 / 0.193 / 0.150 / 0.165 (docs/reconstruction.md): better on
  // the whole, not on every material; a tenth better over the four is the floor here.
  CHECK(sum_weighted < 0.9 * sum_alike);
}

TEST_CASE("pooled: a centre leaves out the colour fringes at an ink's edge", "[pixel][pooled]") {
  // One dark material over a 4-degree card, one group forced; a band of columns through the
  // sample's centre (where the design weighting puts most of the centre's weight, and where
  // inks meet on the colour card) has its red made 3x or a third, pixel by pixel as Bayer
  // phases alternate: a demosaic's fringe beside a bright neighbour. The centre from the fringed
  // observations must score as the centre from clean ones does. Measured: 0.1378 clean, 0.1390
  // fringed; 0.1462 with the fringes kept, and 0.2012 with them left out but their weight lost.
  // 3% is a fifth of the second's own margin and half of the first's.
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const int material = 2;  // black fabric: its signal is small beside any neighbour's
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(4), 1000);
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(32, 32, size, 4, 3);
  std::fill(scene.label.begin(), scene.label.end(), std::uint8_t(material));
  sim::ObservationOptions o;
  o.noise_sigma = 0.02;
  const PixelObservations clean =
      sim::SyntheticObservations(scene, d.continuous, d.views, o, 0, int(scene.label.size()));
  PixelObservations fringed = clean;
  int band_pixels = 0;
  for (int p = 0; p < fringed.pixels; ++p) {
    const int x = p % 32, y = p / 32;
    if (x < 14 || x > 17) continue;
    ++band_pixels;
    for (int v = 0; v < fringed.views; ++v)
      fringed.rgb[3 * fringed.At(p, v)] *= (x + y) % 2 ? 3.0f : 1 / 3.0f;
  }
  PooledOptions one;
  one.groups = 1;
  auto centre_error = [&](const PooledModel& model) {
    return CentreError(model, model.groups.at(0), material, truth);
  };
  const PooledModel from_clean = FitPooledModel(d.basis.View(), clean, PerPixel(), one);
  const PooledModel from_fringed = FitPooledModel(d.basis.View(), fringed, PerPixel(), one);
  const double e_clean = centre_error(from_clean), e_fringed = centre_error(from_fringed);
  WARN("centre from clean observations "
       << e_clean << " (" << from_clean.groups[0].colour_outliers << " left out), from fringed "
       << e_fringed << " (" << from_fringed.groups[0].colour_outliers << " left out; band "
       << band_pixels << " pixels x " << fringed.views << " views)");
  CHECK(from_clean.groups[0].colour_outliers == 0);
  CHECK(from_fringed.groups[0].colour_outliers > band_pixels * fringed.views / 2);
  CHECK(e_fringed < 1.03 * e_clean);
}

TEST_CASE("pooled: one material over a field keeps to its group's centre", "[pixel][pooled]") {
  // White paint alone over a 4-degree card, the model's sizes chosen from the data. Every pixel
  // is the same material, so each could be as good as its group's centre; the pixels off the
  // sample's centre, whose own directions are worse conditioned, must not pull away from it.
  // Judged with the view left out of the centre too, the held-out views chose a weak prior and
  // the field's edges paid (through acqd 0.298 against 0.264 with the centre itself); the
  // strength is judged against the centre from every view (pooled_model.cpp, ChooseStrength).
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(4), 1000);
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(32, 32, size, 4, 3);
  std::fill(scene.label.begin(), scene.label.end(), std::uint8_t(0));
  sim::ObservationOptions o;
  o.noise_sigma = 0.02;  // seeded: the same observations every run
  PooledModel model;
  const PixelSolution pooled = SolvePooled(scene, scene, o, &model);
  REQUIRE(!model.groups.empty());
  const PooledGroup& largest = *std::max_element(
      model.groups.begin(), model.groups.end(),
      [](const PooledGroup& a, const PooledGroup& b) { return a.sample_pixels < b.sample_pixels; });
  const double centre = CentreError(model, largest, 0, truth);
  const double map = MedianPixelError(scene, pooled, truth);
  WARN("white paint over 4 degrees: map " << map << ", its largest group's centre " << centre
                                          << " (strength " << largest.strength << ")\n"
                                          << model.Summary());
  // Measured 0.2808 against the centre's 0.2796 (1.004x); 0.371 (1.33x, strength 20) with the
  // strength judged with the view left out of the centre too. 5% is well clear of both.
  CHECK(map < 1.05 * centre);
}

TEST_CASE("pooled: a centre is fitted from the members it explains", "[pixel][pooled]") {
  // Pink jasper over a 4-degree card, one group forced, with a 4 x 4 patch of brass pixels at
  // the sample's centre, where the design weighting puts the centre's weight (and where the
  // colour card's inks meet): strays that k-means left in the group. The centre must score
  // about as the one from the clean card does. Measured 0.1447 against 0.1326 (1.09x; 16 strays
  // are nearly half the centre's 37 effective pixels, so its first fit leans on them); fitted
  // once from every member 0.8245 against 0.1328 (6.2x). With 4 strays: 1.00x, and 1.02x from
  // every member. 15% is clear of the first and far from the second.
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const int material = 3, stray = 1;
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(4), 1000);
  sim::SyntheticSvbrdf clean = sim::MakeCardLayout(32, 32, size, 4, 3);
  std::fill(clean.label.begin(), clean.label.end(), std::uint8_t(material));
  sim::SyntheticSvbrdf strays = clean;
  for (int y = 14; y < 18; ++y)
    for (int x = 14; x < 18; ++x) strays.label[std::size_t(y * 32 + x)] = std::uint8_t(stray);
  sim::ObservationOptions o;
  o.noise_sigma = 0.02;
  PooledOptions one;
  one.groups = 1;
  auto centre_error = [&](const sim::SyntheticSvbrdf& scene) {
    const PixelObservations obs =
        sim::SyntheticObservations(scene, d.continuous, d.views, o, 0, int(scene.label.size()));
    const PooledModel model = FitPooledModel(d.basis.View(), obs, PerPixel(), one);
    return CentreError(model, model.groups.at(0), material, truth);
  };
  const double e_clean = centre_error(clean), e_strays = centre_error(strays);
  WARN("pink jasper's centre: " << e_clean << " from the clean card, " << e_strays
                                << " with 16 brass strays at the centre");
  CHECK(e_strays < 1.15 * e_clean);
}

TEST_CASE("pooled: members a centre explains worst are kept when they are the material",
          "[pixel][pooled]") {
  // White paint alone over a 10-degree card, one group forced. The members its first centre
  // explains worst are not strays here but the field's far edges, whose own directions are
  // worst conditioned; the centre fitted again without them leans to the rest of the field.
  // Measured: the centre from every member 0.309 (kept by the held-out views), from the 90%
  // explained best 0.400; the same material at 4 degrees 0.280. 20% over the 4-degree centre
  // is clear of the first (1.10x) and far from the second (1.43x).
  const Fixture& d = Data();
  const HeldOutSet truth(d.basis.View(), d.tables);
  const int material = 0;
  sim::ObservationOptions o;
  o.noise_sigma = 0.02;
  PooledOptions one;
  one.groups = 1;
  auto fit_at = [&](double fov) {
    const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(fov), 1000);
    sim::SyntheticSvbrdf scene = sim::MakeCardLayout(32, 32, size, 4, 3);
    std::fill(scene.label.begin(), scene.label.end(), std::uint8_t(material));
    const PixelObservations obs =
        sim::SyntheticObservations(scene, d.continuous, d.views, o, 0, int(scene.label.size()));
    return FitPooledModel(d.basis.View(), obs, PerPixel(), one);
  };
  const PooledModel at4 = fit_at(4), at10 = fit_at(10);
  const double e4 = CentreError(at4, at4.groups.at(0), material, truth);
  const double e10 = CentreError(at10, at10.groups.at(0), material, truth);
  WARN("white paint's centre: " << e4 << " at 4 degrees, " << e10 << " at 10 (from "
                                << at10.groups[0].centre_members << " of "
                                << at10.groups[0].sample_pixels << " members)");
  CHECK(at10.groups[0].centre_members == at10.groups[0].sample_pixels);
  CHECK(e10 < 1.2 * e4);
}

TEST_CASE("pooled: a material the model never saw is solved alone", "[pixel][pooled]") {
  // The model is fitted on a card of three inks; the solve is of a card whose pixels are all
  // the fourth. No centre explains their data, so the prior must lose: each such pixel keeps
  // its independent solve (a thin stroke or a mixed pixel is the same case in small).
  const Fixture& d = Data();
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(4), 1000);
  sim::SyntheticSvbrdf three = sim::MakeCardLayout(40, 40, size, 3, 3);
  sim::SyntheticSvbrdf foreign = three;
  std::fill(foreign.label.begin(), foreign.label.end(), std::uint8_t(3));
  PooledModel model;
  const PixelSolution pooled = SolvePooled(three, foreign, {}, &model);
  const PixelSolution alone = Solve(foreign, d.continuous, {}, PerPixel());
  long solved_alone = 0;
  for (std::size_t p = 0; p < foreign.label.size(); ++p) solved_alone += pooled.group[p] < 0;
  const double share = double(solved_alone) / double(foreign.label.size());
  const HeldOutSet truth(d.basis.View(), d.tables);
  const double e_pooled = MedianPixelError(foreign, pooled, truth);
  const double e_alone = MedianPixelError(foreign, alone, truth);
  WARN("foreign material: " << 100 * share << "% solved alone; error " << e_pooled << " against "
                            << e_alone << " alone");
  // Held-out views judge each pixel with 20 observations: a few may still prefer a wrong
  // centre by chance, so 90% alone and the median within 5% of the independent solve's.
  CHECK(share > 0.9);
  CHECK(e_pooled < 1.05 * e_alone);
}

TEST_CASE("a source's pixels read band by band equal the synthetic source's own", "[pixel]") {
  const Fixture& d = Data();
  sim::ObservationOptions o;
  o.noise_sigma = 0.05;  // seeded per pixel: the same value whichever way a pixel is reached
  sim::SyntheticSource source(sim::MakeCardLayout(20, 13, 40.0, 4, 2), d.continuous, d.views, o);
  const std::vector<std::size_t> indices = {0, 7, 19, 20, 131, 259};
  const PixelObservations direct = source.Pixels(indices, 5);
  const PixelObservations banded = source.ObservationSource::Pixels(indices, 5);
  REQUIRE(direct.pixels == 6);
  REQUIRE(banded.pixels == 6);
  CHECK(direct.views == banded.views);
  for (std::size_t i = 0; i < direct.rgb.size(); ++i)
    REQUIRE((direct.rgb[i] == banded.rgb[i] ||
             (std::isnan(direct.rgb[i]) && std::isnan(banded.rgb[i]))));
  CHECK(direct.light == banded.light);
}

TEST_CASE("pooled: the model is the same from run to run", "[pixel][pooled]") {
  const Fixture& d = Data();
  const double size = NearFieldGeometry::SampleSizeForFov(DegToRad(4), 1000);
  const sim::SyntheticSvbrdf scene = sim::MakeCardLayout(32, 32, size, 4, 5);
  const PixelObservations obs =
      sim::SyntheticObservations(scene, d.continuous, d.views, {}, 0, int(scene.label.size()));
  const PooledModel a = FitPooledModel(d.basis.View(), obs, PerPixel(), PooledOptions{});
  const PooledModel b = FitPooledModel(d.basis.View(), obs, PerPixel(), PooledOptions{});
  REQUIRE(a.groups.size() == b.groups.size());
  for (std::size_t g = 0; g < a.groups.size(); ++g) {
    CHECK(a.groups[g].centre == b.groups[g].centre);
    CHECK(a.groups[g].strength == b.groups[g].strength);
  }
  // Forced sizes are taken as given.
  PooledOptions forced;
  forced.groups = 7;
  CHECK(FitPooledModel(d.basis.View(), obs, PerPixel(), forced).groups.size() <= 7);
  PooledOptions bad;
  bad.groups = -1;
  CHECK_THROWS_AS(bad.Check(), UserError);
}

TEST_CASE("samples: blends are exact mixtures, files are checked", "[pixel][samples]") {
  const Fixture& d = Data();
  const sim::MixedSample blend = sim::MakeSample(SampleKind::kBlend, 64, 4, 10.0, 2, 1);
  CHECK(blend.mixtures.size() == 17);  // weights 0, 1/16, ..., 1
  for (int x = 1; x < 64; ++x) {       // the weight of material 1 grows left to right
    const auto& a = blend.mixtures[blend.layout.label[x - 1]];
    const auto& b = blend.mixtures[blend.layout.label[x]];
    const double wa = a.back().first == 1 ? a.back().second : 0;
    const double wb = b.back().first == 1 ? b.back().second : 0;
    REQUIRE(wb >= wa);
  }
  // A mixture's truth is the weighted sum of its materials', in the network and in the table.
  const std::vector<sim::GroundTruth> base = {d.continuous[0], d.continuous[1]};
  const std::vector<sim::GroundTruth> truth = blend.Truths(base);
  const std::vector<MerlBrdf> tables = blend.Tables({d.tables[0], d.tables[1]});
  for (std::size_t m = 0; m < blend.mixtures.size(); ++m) {
    if (blend.mixtures[m].size() != 2) continue;
    const double w = blend.mixtures[m][1].second;
    const DirectionPair dirs{Eigen::Vector3d(0.3, 0.1, 0.95).normalized(),
                             Eigen::Vector3d(-0.2, 0.2, 0.96).normalized()};
    const auto mixed = truth[m].Value(dirs);
    const auto a = base[0].Value(dirs), b = base[1].Value(dirs);
    CHECK(mixed[1] == Approx((1 - w) * a[1] + w * b[1]).epsilon(1e-12));
    const std::size_t bin = 123456;
    if (d.tables[0].raw[bin] >= 0 && d.tables[1].raw[bin] >= 0)
      CHECK(tables[m].raw[bin] ==
            Approx((1 - w) * d.tables[0].raw[bin] + w * d.tables[1].raw[bin]));
  }
  for (SampleKind k : {SampleKind::kMarble, SampleKind::kText}) {
    const sim::MixedSample s = sim::MakeSample(k, 48, 48, 10.0, 2, 3);
    CHECK(s.mixtures.size() >= 2);
    for (std::uint8_t l : s.layout.label) REQUIRE(l < s.mixtures.size());
  }

  test::TempDir dir;
  FloatPlanes labels;
  labels.width = 3, labels.height = 2;
  labels.planes["label"] = {0, 1, 1, 0, 5, 0};
  WriteFloatPlanesExr(dir / "labels.exr", labels);
  CHECK_THROWS_WITH(sim::ReadSampleLabels(dir / "labels.exr", 2, 10.0),
                    Catch::Contains("labels.exr") && Catch::Contains("pixel (1, 1) has label 5"));
  labels.planes["label"][4] = 1;
  WriteFloatPlanesExr(dir / "labels.exr", labels);
  CHECK(sim::ReadSampleLabels(dir / "labels.exr", 2, 10.0).layout.label[4] == 1);

  FloatPlanes weights;
  weights.width = 2, weights.height = 1;
  weights.planes["white-paint"] = {0.25f, 0.5f};
  weights.planes["brass"] = {0.75f, 0.3f};  // the second pixel sums to 0.8
  WriteFloatPlanesExr(dir / "weights.exr", weights);
  const std::vector<std::string> names = {"white-paint", "brass"};
  CHECK_THROWS_WITH(sim::ReadSampleWeights(dir / "weights.exr", names, 10.0),
                    Catch::Contains("weights.exr") && Catch::Contains("pixel (1, 0)") &&
                        Catch::Contains("sum to 0.8"));
  CHECK_THROWS_WITH(sim::ReadSampleWeights(dir / "weights.exr", {"white-paint", "gold"}, 10.0),
                    Catch::Contains("weights.exr") && Catch::Contains("gold"));
  weights.planes["brass"] = {0.75f, -0.5f};
  weights.planes["white-paint"] = {0.25f, 1.5f};
  WriteFloatPlanesExr(dir / "weights.exr", weights);
  CHECK_THROWS_WITH(sim::ReadSampleWeights(dir / "weights.exr", names, 10.0),
                    Catch::Contains("must be >= 0"));
  weights.planes["brass"] = {0.75f, 0.5f};
  weights.planes["white-paint"] = {0.25f, 0.5f};
  WriteFloatPlanesExr(dir / "weights.exr", weights);
  const sim::MixedSample ok = sim::ReadSampleWeights(dir / "weights.exr", names, 10.0);
  CHECK(ok.mixtures.size() == 2);
  CHECK(ok.Names(names)[ok.layout.label[1]] == "0.5 white-paint + 0.5 brass");
}

// Per-pixel normals (issue 19).

TEST_CASE("a tilted facet's observations, turned into its frame, are its BRDF there", "[normals]") {
  const Fixture& d = Data();
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(4, 4, 20.0, 1, 1);
  const Eigen::Vector3f n = NormalOfSlope(0.12f, -0.07f);  // 7.9 degrees
  scene.normal.assign(scene.label.size(), n);
  const std::vector<sim::GroundTruth> brass = {d.continuous[1]};
  const PixelObservations obs =
      sim::SyntheticObservations(scene, brass, d.views, {}, 0, int(scene.label.size()));
  PixelObservations turned;
  turned.Resize(obs.pixels, obs.views);
  int compared = 0;
  for (int p = 0; p < obs.pixels; ++p) {
    ToFacetFrame(n, 0.0, obs, p, &turned, p);
    for (int v = 0; v < obs.views; ++v) {
      const std::size_t i = obs.At(p, v);
      if (std::isnan(obs.rgb[3 * i])) continue;
      const auto truth =
          brass[0].Value({turned.light[i].cast<double>(), turned.camera[i].cast<double>()});
      // float directions and values: 1e-3 relative is a few float roundings of a steep lobe.
      for (int c = 0; c < 3; ++c)
        CHECK(turned.rgb[3 * i + c] == Approx(truth[c]).epsilon(1e-3).margin(1e-6));
      ++compared;
    }
  }
  CHECK(compared > obs.pixels * obs.views / 2);
}

TEST_CASE(
    "a facet's BRDF seen as if flat: the one rule the renderer, the renders and the scoring share",
    "[normals]") {
  // A facet BRDF that returns its facet-frame directions' z: what the rule turned them into.
  const auto facet = [](const Eigen::Vector3d& in, const Eigen::Vector3d& out) {
    return std::array<double, 3>{in.z(), out.z(), 1.0};
  };
  const Eigen::Vector3d in = Eigen::Vector3d(0.3, -0.2, 0.8).normalized();
  const Eigen::Vector3d out = Eigen::Vector3d(-0.4, 0.1, 0.9).normalized();
  // The sample's normal: the directions unchanged, the value unscaled.
  const std::array<double, 3> flat = SeenAsFlat(Eigen::Vector3f::UnitZ(), in, out, facet);
  CHECK(flat[0] == Approx(in.z()));
  CHECK(flat[1] == Approx(out.z()));
  CHECK(flat[2] == Approx(1.0));
  // A tilted facet: the value at its frame's directions times n.l / l.z.
  const Eigen::Vector3f n = NormalOfSlope(0.2f, -0.1f);
  const std::array<double, 3> tilted = SeenAsFlat(n, in, out, facet);
  const double n_l = n.cast<double>().dot(in), n_v = n.cast<double>().dot(out);
  CHECK(tilted[0] == Approx(n_l * n_l / in.z()));
  CHECK(tilted[1] == Approx(n_v * n_l / in.z()));
  CHECK(tilted[2] == Approx(n_l / in.z()));
  // A facet turned away from the light, or hidden from the camera: dark.
  const Eigen::Vector3d grazing = Eigen::Vector3d(1, 0, 0.05).normalized();
  CHECK(SeenAsFlat(NormalOfSlope(-0.5f, 0), grazing, out, facet)[2] == 0);
  CHECK(SeenAsFlat(NormalOfSlope(-0.5f, 0), out, grazing, facet)[2] == 0);
}

TEST_CASE("the simulated camera renders a tilted facet as the synthetic observations measure it",
          "[normals]") {
  // acqd's simulated instrument (sample_renderer.h) and `acq reconstruct synthetic`
  // (synthetic_svbrdf.h) must agree on relief: one convention, core/facet_frame.h.
  const Fixture& d = Data();
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(3, 3, 30.0, 1, 1);
  scene.normal.assign(scene.label.size(), NormalOfSlope(0.1f, 0.15f));  // 10.2 degrees
  sim::ObservationOptions o;
  o.geometry.sample_size_mm = scene.sample_size_mm;
  const PixelObservations obs =
      sim::SyntheticObservations(scene, {d.continuous[1]}, d.views, o, 0, int(scene.label.size()));
  sim::RenderScene render;
  render.kind = sim::RenderScene::Kind::kCard;
  render.sample_size_mm = scene.sample_size_mm;
  render.card = scene;
  render.materials = {d.continuous[1]};
  int compared = 0, dark = 0;
  for (int p = 0; p < obs.pixels; ++p)
    for (int v = 0; v < obs.views; ++v) {
      const Eigen::Vector2d point = scene.PointOf(p);
      const DirectionPair far = DirectionsOf(d.views[std::size_t(v)]);
      sim::PointLight light;
      light.position_mm = o.geometry.light_distance_mm * far.in;
      const Eigen::Vector3d eye = o.geometry.camera_distance_mm * far.out;
      const std::array<double, 3> radiance = sim::RadianceAt(render, point, eye, light);
      const Eigen::Vector3d to_light = light.position_mm - Eigen::Vector3d(point.x(), point.y(), 0);
      // The radiance over the irradiance of the sample plane: the BRDF measured as if flat.
      const double irradiance =
          light.intensity * to_light.normalized().z() / to_light.squaredNorm();
      const float* measured = &obs.rgb[3 * obs.At(p, v)];
      for (int c = 0; c < 3; ++c)
        CHECK(radiance[c] / irradiance == Approx(measured[c]).epsilon(1e-4).margin(1e-7));
      // The facet hides the view or shadows the light: dark in both, not missing.
      const Eigen::Matrix3f r = FacetFromSample(scene.normal[std::size_t(p)]);
      const bool turned_away =
          (r * obs.light[obs.At(p, v)]).z() <= 0 || (r * obs.camera[obs.At(p, v)]).z() <= 0;
      if (turned_away) CHECK(measured[0] == 0);
      dark += turned_away;
      ++compared;
    }
  CHECK(compared == obs.pixels * obs.views);
  // The set's grazing lights (85-89 degrees) fall behind a facet tilted 10 degrees away.
  CHECK(dark > 0);
}

// An embossed card, 48 x 48 pixels filling 4 degrees at 1 m, of the fixture's materials `inks`
// (by default brass alone): what is printed and a raised border embossed, 10 degree slopes;
// `noise` multiplicative.
struct EmbossedCard {
  sim::SyntheticSvbrdf scene;
  PixelObservations obs;
  explicit EmbossedCard(const Fixture& d, double noise = 0, const std::vector<int>& inks = {1})
      : scene(sim::MakeCardLayout(48, 48, 2000.0 * std::tan(DegToRad(2.0)), int(inks.size()), 1)) {
    sim::ReliefOptions relief;
    relief.slope_deg = 10;
    relief.border_share = 0.15;
    sim::SetNormalsFromHeight(&scene, sim::CardRelief(scene, relief));
    sim::ObservationOptions o;
    o.geometry.sample_size_mm = scene.sample_size_mm;
    o.noise_sigma = noise;
    std::vector<sim::GroundTruth> materials;
    for (int i : inks) materials.push_back(d.continuous[std::size_t(i)]);
    obs = sim::SyntheticObservations(scene, materials, d.views, o, 0, int(scene.label.size()));
  }
};

TEST_CASE("normals of an embossed glossy card are recovered; flat areas stay flat", "[normals]") {
  const Fixture& d = Data();
  EmbossedCard card(d);
  const sim::SyntheticSvbrdf& scene = card.scene;
  PixelObservations& obs = card.obs;
  NormalSearchOptions search;
  search.enabled = true;
  search.prior = 2;
  // The material groups the search judges by, fitted on the card's pixels taken as flat, as
  // the reconstruction fits them on its sample.
  const PooledModel reference = FitNormalReference(d.basis.View(), obs, PerPixel(), {}, search);
  const PixelNormals normals =
      EstimateNormals(d.basis.View(), &obs, PerPixel(), search, &reference);
  std::vector<double> relief_error, flat_error, assumed_error;
  int refused = 0;
  for (std::size_t p = 0; p < scene.label.size(); ++p) {
    const Eigen::Vector3f truth = scene.normal[p];
    REQUIRE(normals.normal[p].allFinite());
    CHECK(normals.normal[p].norm() == Approx(1.0).epsilon(1e-5));
    const double tilt = NormalAngle(truth, Eigen::Vector3f::UnitZ());
    const double error = RadToDeg(NormalAngle(truth, normals.normal[p]));
    if (tilt > DegToRad(0.5)) {
      relief_error.push_back(error);
      assumed_error.push_back(RadToDeg(tilt));
    }
    if (tilt < DegToRad(0.05)) flat_error.push_back(error);
    refused += normals.status[p] == NormalStatus::kRefused;
  }
  REQUIRE(relief_error.size() > 100);
  REQUIRE(flat_error.size() > 100);
  // The issue's goals (2 degrees over the relief, 0.5 of false tilt on flat areas); measured
  // here 1.21 and 0.00 (criterion centre), against 4.6 degrees for the sample's normal assumed.
  INFO("relief " << Median(relief_error) << ", flat " << Median(flat_error));
  // The reference takes a tilted pixel's colour (brass's highlight caught or missed) as data to
  // judge normals by, not as a fringe to leave out (PooledOptions::leave_out_colour_fringes):
  // with fringes left out the relief's error was 1.49 degrees here, 2.77 against 1.27 on the
  // normals study's 128 x 128 brass card.
  for (const PooledGroup& g : reference.groups) CHECK(g.colour_outliers == 0);
  CHECK(Median(relief_error) < 2.0);
  CHECK(Median(flat_error) < 0.5);
  CHECK(Median(assumed_error) > 3.0);
  // Relief inside the cone is not flagged as too steep (no view it faces is seen dark);
  // measured: none refused. A percent allows for a grazing view's noise.
  INFO("refused " << refused);
  CHECK(refused <= int(scene.label.size()) / 100);
}

TEST_CASE("a normal's uncertainty grows with the noise, foretells its error, and can refuse it",
          "[normals]") {
  const Fixture& d = Data();
  // The embossed brass card, clean and with 10% noise: noisier data fix a normal less well.
  struct Estimate {
    std::vector<double> certain, uncertain;  // relief errors, uncertainty within 1 degree or not
    std::vector<double> uncertainty;         // of the estimated pixels
    int refused = 0;
  };
  const auto estimate = [&](double noise, double limit) {
    EmbossedCard card(d, noise);
    NormalSearchOptions search;
    search.enabled = true;
    search.prior = 2;
    search.max_uncertainty_deg = limit;
    const PooledModel reference =
        FitNormalReference(d.basis.View(), card.obs, PerPixel(), {}, search);
    const PixelNormals normals =
        EstimateNormals(d.basis.View(), &card.obs, PerPixel(), search, &reference);
    Estimate e;
    for (std::size_t p = 0; p < card.scene.label.size(); ++p) {
      const float radius = normals.uncertainty_deg[p];
      REQUIRE(std::isfinite(radius));
      if (normals.status[p] == NormalStatus::kRefused && radius >= 0) {
        // Refused for its uncertainty: only with a limit, and only beyond it.
        CHECK(limit > 0);
        CHECK(radius > limit);
        ++e.refused;
      }
      if (normals.status[p] != NormalStatus::kEstimated) {
        if (normals.status[p] != NormalStatus::kRefused) CHECK(radius == kNoNormalUncertainty);
        continue;
      }
      CHECK(radius >= 0);
      if (limit > 0) CHECK(radius <= limit);
      e.uncertainty.push_back(radius);
      const Eigen::Vector3f truth = card.scene.normal[p];
      if (NormalAngle(truth, Eigen::Vector3f::UnitZ()) > DegToRad(0.5))
        (radius <= 1.0 ? e.certain : e.uncertain)
            .push_back(RadToDeg(NormalAngle(truth, normals.normal[p])));
    }
    return e;
  };
  const Estimate clean = estimate(0, 0), noisy = estimate(0.1, 0);
  REQUIRE(clean.uncertainty.size() > 100);
  REQUIRE(noisy.uncertain.size() > 20);
  REQUIRE(noisy.certain.size() > 20);
  // The uncertainty takes the search's steps (the finest 0.21 degree): compared by the share of
  // estimated pixels over a degree.
  const auto beyond = [](const Estimate& e) {
    return std::count_if(e.uncertainty.begin(), e.uncertainty.end(),
                         [](double r) { return r > 1.0; });
  };
  const double clean_share = double(beyond(clean)) / double(clean.uncertainty.size());
  const double noisy_share = double(beyond(noisy)) / double(noisy.uncertainty.size());
  INFO("estimated pixels over a degree: clean "
       << clean_share << ", noisy " << noisy_share << "; noisy relief error "
       << Median(noisy.certain) << " where certain (" << noisy.certain.size() << "), "
       << Median(noisy.uncertain) << " where not (" << noisy.uncertain.size() << ")");
  CHECK(noisy_share > clean_share);
  // Measured: 0.22 degree against 1.23; twice leaves room for the basis and search to change.
  CHECK(Median(noisy.uncertain) > 2 * Median(noisy.certain));
  // A limit refuses the pixels beyond it and keeps the rest as they were.
  const Estimate limited = estimate(0.1, 1.0);
  INFO("refused for their uncertainty: " << limited.refused);
  CHECK(limited.refused == int(beyond(noisy)));
  CHECK(limited.certain == noisy.certain);
}

TEST_CASE("one view holding another facet's highlight does not drag a normal off", "[normals]") {
  const Fixture& d = Data();
  // The embossed brass card above; at every pixel on the relief one view, drawn at random, is
  // made 8 times brighter: a footprint that straddles facets catches another facet's highlight
  // there, which no single normal explains (through acqd, the pixels at a slope's foot).
  const EmbossedCard card(d);
  const sim::SyntheticSvbrdf& scene = card.scene;
  const PixelObservations& clean = card.obs;
  PixelObservations obs = clean;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, obs.views - 1);
  const auto on_relief = [&](std::size_t p) {
    return NormalAngle(scene.normal[p], Eigen::Vector3f::UnitZ()) > DegToRad(0.5);
  };
  for (int p = 0; p < obs.pixels; ++p)
    if (on_relief(std::size_t(p))) {
      const int v = pick(rng);
      for (int c = 0; c < 3; ++c) obs.rgb[3 * obs.At(p, v) + c] *= 8;
    }
  const auto relief_error = [&](int trimmed) {
    NormalSearchOptions search;
    search.enabled = true;
    search.prior = 2;
    search.trimmed_views = trimmed;
    PixelObservations turned = obs;
    const PooledModel reference = FitNormalReference(d.basis.View(), clean, PerPixel(), {}, search);
    const PixelNormals normals =
        EstimateNormals(d.basis.View(), &turned, PerPixel(), search, &reference);
    std::vector<double> error;
    for (std::size_t p = 0; p < scene.label.size(); ++p) {
      REQUIRE(normals.normal[p].allFinite());
      if (on_relief(p)) error.push_back(RadToDeg(NormalAngle(scene.normal[p], normals.normal[p])));
    }
    return Median(error);
  };
  const double trimmed = relief_error(1), untrimmed = relief_error(0);
  INFO("relief: worst view left out " << trimmed << " deg, every view scored " << untrimmed);
  // Measured: 0.23 degrees with the worst view left out of each score, as on the clean card
  // (0.23 either way), and 0.51 with every view scored. The bounds leave room for the basis and
  // the search to change: the issue's 2 degrees, and a clear loss without the trim.
  CHECK(trimmed < 2.0);
  CHECK(untrimmed > 1.5 * trimmed);
}

TEST_CASE("the normal reference's groups are materials, not a material's relief", "[normals]") {
  const Fixture& d = Data();
  const double size_mm = 2000.0 * std::tan(DegToRad(2.0));  // 4 degrees at 1 m
  NormalSearchOptions search;
  search.enabled = true;
  // Without the search (enabled false) the reference keeps every group its model found: the
  // groups as the map's model would cut them.
  const auto grouped_and_kept = [&](const PixelObservations& obs) {
    const PooledModel all = FitNormalReference(d.basis.View(), obs, PerPixel(), {}, {});
    const PooledModel kept = FitNormalReference(d.basis.View(), obs, PerPixel(), {}, search);
    return std::pair{all.groups.size(), kept.groups.size()};
  };
  sim::ObservationOptions o;
  o.geometry.sample_size_mm = size_mm;
  // Brass alone with a raised border of 10 degree slopes: the border's tilted pixels get groups
  // of their own, which would explain them as flat; brass's centre tilted explains them better
  // than their own centres do, and they go. Measured: 8 groups, 2 kept.
  sim::SyntheticSvbrdf brass = sim::MakeCardLayout(48, 48, size_mm, 1, 1);
  sim::ReliefOptions relief;
  relief.slope_deg = 10;
  relief.border_share = 0.15;
  sim::SetNormalsFromHeight(&brass, sim::CardRelief(brass, relief));
  const auto [brass_grouped, brass_kept] = grouped_and_kept(
      sim::SyntheticObservations(brass, {d.continuous[1]}, d.views, o, 0, int(brass.label.size())));
  INFO("brass with relief: " << brass_grouped << " groups, " << brass_kept << " kept");
  CHECK(brass_grouped > 2);
  CHECK(brass_kept <= 2);
  // Flat white paint with pink-jasper prints: no group is another's relief, and no tilt of white
  // paint explains pink jasper (the failure this guards against: pink jasper judged by white
  // paint's centre, tilted 0.47 degrees through acqd). Measured: 4 groups, 4 kept.
  sim::SyntheticSvbrdf card = sim::MakeCardLayout(48, 48, size_mm, 2, 1);
  const auto [flat_grouped, flat_kept] = grouped_and_kept(sim::SyntheticObservations(
      card, {d.continuous[0], d.continuous[3]}, d.views, o, 0, int(card.label.size())));
  INFO("flat white paint and pink jasper: " << flat_grouped << " groups, " << flat_kept << " kept");
  CHECK(flat_grouped >= 2);
  CHECK(flat_kept == flat_grouped);
}

// Observations of `scene` whose pixels at an ink edge (a 4-neighbour of another material) are
// the linear mixture, half and half, of their material and that neighbour's: what a camera's
// pixel straddling the edge sees. Each material's observations are made at every pixel (the
// scene's normals) and mixed after; returns the mixed pixels' indices too.
PixelObservations MixedEdgeObservations(const sim::SyntheticSvbrdf& scene,
                                        const std::vector<sim::GroundTruth>& materials,
                                        std::vector<int>* mixed) {
  const Fixture& d = Data();
  sim::ObservationOptions o;
  o.geometry.sample_size_mm = scene.sample_size_mm;
  const int pixels = int(scene.label.size());
  std::vector<PixelObservations> each;
  for (const sim::GroundTruth& m : materials) {
    sim::SyntheticSvbrdf one = scene;
    one.label.assign(scene.label.size(), 0);
    each.push_back(sim::SyntheticObservations(one, {m}, d.views, o, 0, pixels));
  }
  PixelObservations obs = each[0];
  const int w = scene.width, h = scene.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int p = y * w + x, own = scene.label[std::size_t(p)];
      int other = own;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx >= 0 && nx < w && ny >= 0 && ny < h && scene.label[std::size_t(ny * w + nx)] != own)
          other = scene.label[std::size_t(ny * w + nx)];
      }
      // The paper's side of an edge mixed (label 0 next to an ink), so that a stroke a pixel or
      // two wide keeps pure pixels.
      const float share = own == 0 && other != own ? 0.5f : 1.0f;
      if (share < 1) mixed->push_back(p);
      for (int v = 0; v < obs.views; ++v)
        for (int c = 0; c < 3; ++c) {
          const std::size_t i = 3 * obs.At(p, v) + std::size_t(c);
          obs.rgb[i] =
              share * each[std::size_t(own)].rgb[i] + (1 - share) * each[std::size_t(other)].rgb[i];
        }
    }
  return obs;
}

// A 48 x 48 card of four inks printed embossed (10 degree edges) on white paint, 4 degrees of
// field of view.
sim::SyntheticSvbrdf EmbossedInkCard() {
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(48, 48, 2000.0 * std::tan(DegToRad(2.0)), 4, 3);
  sim::ReliefOptions relief;
  relief.slope_deg = 10;
  sim::SetNormalsFromHeight(&scene, sim::CardRelief(scene, relief));
  return scene;
}

TEST_CASE("a mixed pixel at an embossed ink edge is judged by two inks' centres mixed",
          "[normals]") {
  const Fixture& d = Data();
  // Inks printed embossed (10 degree edges) on white paint: the relief is where the inks meet
  // the paint, so a pixel straddling an edge is both tilted and mixed.
  sim::SyntheticSvbrdf scene = EmbossedInkCard();
  std::vector<int> mixed;
  const PixelObservations observed = MixedEdgeObservations(scene, d.continuous, &mixed);
  // The reference given the card's four inks (on so small a card the held-out views choose
  // fewer groups): the search's choice among their centres is what is tested.
  PooledOptions four_inks;
  four_inks.groups = 4;
  NormalSearchOptions searched;
  searched.enabled = true;
  const PooledModel reference =
      FitNormalReference(d.basis.View(), observed, PerPixel(), four_inks, searched);
  const auto errors = [&](bool mixtures) {
    NormalSearchOptions search;
    search.enabled = true;
    search.mixed_pixels = mixtures;
    PixelObservations obs = observed;
    const PixelNormals normals =
        EstimateNormals(d.basis.View(), &obs, PerPixel(), search, &reference);
    std::vector<double> at_edges, flat;
    for (std::size_t p = 0; p < scene.label.size(); ++p) {
      REQUIRE(normals.normal[p].allFinite());
      const double error = RadToDeg(NormalAngle(scene.normal[p], normals.normal[p]));
      const bool tilted = NormalAngle(scene.normal[p], Eigen::Vector3f::UnitZ()) > DegToRad(0.5);
      const bool is_mixed = std::binary_search(mixed.begin(), mixed.end(), int(p));
      if (tilted && is_mixed) at_edges.push_back(error);
      if (!is_mixed && NormalAngle(scene.normal[p], Eigen::Vector3f::UnitZ()) < DegToRad(0.05))
        flat.push_back(error);
    }
    REQUIRE(at_edges.size() > 50);
    REQUIRE(flat.size() > 100);
    return std::pair{Median(at_edges), Median(flat)};
  };
  const auto [one_centre, one_centre_flat] = errors(false);
  const auto [two_centres, two_centres_flat] = errors(true);
  INFO("mixed tilted pixels: one centre " << one_centre << ", two mixed " << two_centres
                                          << "; flat " << one_centre_flat << ", "
                                          << two_centres_flat);
  // Measured: 2.35 degrees judged by one centre, 1.28 by two mixed; false tilt 0.31 either way.
  // A quarter better is far outside what the search's grid steps (0.2-0.3 degree) move.
  CHECK(two_centres < 0.75 * one_centre);
  CHECK(two_centres < 2.0);  // the issue's goal over relief
  CHECK(two_centres_flat < 0.5);
}

TEST_CASE("a tilt only another ink's centre explains keeps the sample's normal", "[normals]") {
  const Fixture& d = Data();
  // The embossed ink card with its edge pixels mixed (each a share of two inks, at the edge's
  // tilt): where a footprint straddles inks, a tilt can be explained by a glossier ink than the
  // one that explains the pixel flat.
  sim::SyntheticSvbrdf scene = EmbossedInkCard();
  std::vector<int> mixed;
  const PixelObservations observed = MixedEdgeObservations(scene, d.continuous, &mixed);
  NormalSearchOptions search;
  search.enabled = true;
  const PooledModel reference =
      FitNormalReference(d.basis.View(), observed, PerPixel(), {}, search);
  INFO("reference groups " << reference.groups.size());
  const auto estimate = [&](const PooledModel& by, bool same_centre) {
    NormalSearchOptions o = search;
    o.same_centre = same_centre;
    PixelObservations obs = observed;
    return EstimateNormals(d.basis.View(), &obs, PerPixel(), o, &by);
  };
  const PixelNormals free = estimate(reference, false), kept = estimate(reference, true);
  int kept_back = 0;
  std::vector<double> relief_error, relief_error_free, kept_back_error;  // degrees
  for (std::size_t p = 0; p < scene.label.size(); ++p) {
    // The rule only keeps normals back: every normal it lets through is the same one.
    if (kept.status[p] == NormalStatus::kEstimated) {
      CHECK(free.status[p] == NormalStatus::kEstimated);
      CHECK(kept.normal[p] == free.normal[p]);
    } else if (free.status[p] == NormalStatus::kEstimated) {
      ++kept_back;
      CHECK(kept.status[p] == NormalStatus::kNoEvidence);
      CHECK(kept.normal[p] == Eigen::Vector3f::UnitZ());
    } else {
      CHECK(kept.status[p] == free.status[p]);
    }
    if (NormalAngle(scene.normal[p], Eigen::Vector3f::UnitZ()) > DegToRad(0.5)) {
      relief_error.push_back(RadToDeg(NormalAngle(scene.normal[p], kept.normal[p])));
      relief_error_free.push_back(RadToDeg(NormalAngle(scene.normal[p], free.normal[p])));
      if (free.status[p] == NormalStatus::kEstimated && kept.status[p] != NormalStatus::kEstimated)
        kept_back_error.push_back(RadToDeg(NormalAngle(scene.normal[p], free.normal[p])));
    }
  }
  INFO("kept back " << kept_back << " (" << kept_back_error.size() << " on the relief, their "
                    << "normals " << Median(kept_back_error) << " degrees off); relief "
                    << Median(relief_error) << " (without the rule " << Median(relief_error_free)
                    << ")");
  REQUIRE(kept_back > 0);  // else this test says nothing
  // Measured: 117 kept back, all on the relief, their normals 3.7 degrees off (median); the
  // relief 1.36 degrees, 1.32 without the rule: the goal (2) still met.
  CHECK(Median(relief_error) < 2.0);
  // A forced number of groups is not checked to be materials (one may be a relief, judging
  // relief pixels flat): the rule stands aside. Measured before it did: with four groups
  // forced it kept back 389 normals and the relief went from 1.72 to 2.79 degrees.
  PooledOptions four_groups;
  four_groups.groups = 4;
  const PooledModel forced =
      FitNormalReference(d.basis.View(), observed, PerPixel(), four_groups, search);
  REQUIRE_FALSE(forced.groups_are_materials);
  CHECK(estimate(forced, true).status == estimate(forced, false).status);
}

TEST_CASE("a view the centre fits badly cannot be dropped by tilting away from it", "[normals]") {
  const Fixture& d = Data();
  // Flat white paint, 40 mm at 1 m (the example plan's): the grazing light's zenith varies by
  // 2.3 degrees over it, so at some pixels a tilt of a fraction of a degree hides it.
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(24, 24, 40.0, 1, 1);
  PixelObservations obs =
      sim::SyntheticObservations(scene, {d.continuous[0]}, d.views, {}, 0, int(scene.label.size()));
  NormalSearchOptions search;
  search.enabled = true;
  // The tilts that would hide the light are fractions of a degree: kept, so that what stops them
  // is the charge for the darkness, not the minimum tilt.
  search.min_tilt_deg = 0;
  const PooledModel reference = FitNormalReference(d.basis.View(), obs, PerPixel(), {}, search);
  // The most grazing light (88.75 degrees from the normal at the centre): every pixel's value
  // there made 4x too bright, which no centre fits; dropping the view by a tilt that puts the
  // light behind the facet would lower the misfit by far more than the prior costs.
  int grazing = 0;
  for (int v = 1; v < obs.views; ++v)
    if (obs.light[obs.At(0, v)].z() < obs.light[obs.At(0, grazing)].z()) grazing = v;
  REQUIRE(obs.light[obs.At(0, grazing)].z() < 0.05);
  for (int p = 0; p < obs.pixels; ++p)
    for (int c = 0; c < 3; ++c) obs.rgb[3 * obs.At(p, grazing) + c] *= 4;
  const PixelObservations before = obs;
  const PixelNormals normals =
      EstimateNormals(d.basis.View(), &obs, PerPixel(), search, &reference);
  int behind = 0, estimated = 0;
  for (int p = 0; p < obs.pixels; ++p) {
    const Eigen::Vector3f l =
        FacetFromSample(normals.normal[p]) * before.light[before.At(p, grazing)];
    behind += l.z() <= 0;
    estimated += normals.status[p] == NormalStatus::kEstimated;
  }
  INFO("estimated " << estimated);
  // Charged as the darkness it would be, the light stays in front of every facet but a few;
  // measured: 0 of 576 behind, and 63 when the view could be dropped for free.
  INFO("facets turned away from the grazing light: " << behind << " of " << obs.pixels);
  CHECK(estimated > obs.pixels / 2);
  CHECK(behind < obs.pixels / 50);
}

// The embossed brass card's observations recorded with each view's directions a little off, as a
// calibration leaves them: light and camera turned together by `error_deg` about an axis drawn
// per view (seeded), the same at every pixel.
void TurnRecordedViews(PixelObservations* obs, double error_deg, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> axis(0.0f, 1.0f);
  for (int v = 0; v < obs->views; ++v) {
    const Eigen::Vector3f a = Eigen::Vector3f(axis(rng), axis(rng), axis(rng)).normalized();
    const Eigen::Matrix3f turn =
        Eigen::AngleAxisf(float(DegToRad(error_deg)), a).toRotationMatrix();
    for (int p = 0; p < obs->pixels; ++p) {
      obs->light[obs->At(p, v)] = (turn * obs->light[obs->At(p, v)]).normalized();
      obs->camera[obs->At(p, v)] = (turn * obs->camera[obs->At(p, v)]).normalized();
    }
  }
}

struct NormalErrors {
  double relief = 0, flat = 0;  // medians (degrees): error over the relief, tilt on flat areas
  double smallest_tilt = 90;    // of the estimated normals (degrees)
};

NormalErrors SearchEmbossedCard(const Fixture& d, const EmbossedCard& card,
                                const NormalSearchOptions& search) {
  PixelObservations obs = card.obs;
  const PooledModel reference = FitNormalReference(d.basis.View(), obs, PerPixel(), {}, search);
  const PixelNormals normals =
      EstimateNormals(d.basis.View(), &obs, PerPixel(), search, &reference);
  std::vector<double> relief, flat;
  NormalErrors e;
  for (std::size_t p = 0; p < card.scene.label.size(); ++p) {
    const Eigen::Vector3f truth = card.scene.normal[p];
    const double error = RadToDeg(NormalAngle(truth, normals.normal[p]));
    const double tilt = NormalAngle(truth, Eigen::Vector3f::UnitZ());
    if (tilt > DegToRad(0.5)) relief.push_back(error);
    if (tilt < DegToRad(0.05)) flat.push_back(error);
    if (normals.status[p] == NormalStatus::kEstimated)
      e.smallest_tilt = std::min(
          e.smallest_tilt, RadToDeg(NormalAngle(normals.normal[p], Eigen::Vector3f::UnitZ())));
  }
  e.relief = Median(relief);
  e.flat = Median(flat);
  return e;
}

TEST_CASE("a calibration's direction error tilts flat areas; a minimum tilt keeps them flat",
          "[normals]") {
  const Fixture& d = Data();
  EmbossedCard card(d, 0.02);
  TurnRecordedViews(&card.obs, 0.4, 7);
  NormalSearchOptions search;
  search.enabled = true;
  search.prior = 2;
  search.min_tilt_deg = 0;
  const NormalErrors free = SearchEmbossedCard(d, card, search);
  search.min_tilt_deg = kDefaultNormalsMinTiltDeg;
  const NormalErrors floored = SearchEmbossedCard(d, card, search);
  INFO("relief " << free.relief << " -> " << floored.relief << ", flat " << free.flat << " -> "
                 << floored.flat << ", smallest tilt kept " << floored.smallest_tilt);
  // Measured: flat 0.21 -> 0 degree, the relief 0.46 -> 0.54; the directions turned by 0.4
  // degree tilt the flat brass as a relief would.
  CHECK(free.flat > 0.1);
  CHECK(floored.smallest_tilt >= kDefaultNormalsMinTiltDeg - 1e-3);
  CHECK(floored.flat == 0);
  CHECK(floored.relief < 2.0);
}

TEST_CASE("views the centre fits worst weigh least in a normal's score", "[normals]") {
  const Fixture& d = Data();
  // White paint with brass printed on it, both embossed: white paint's centre misses its own
  // pixels most at the views near its peak.
  EmbossedCard card(d, 0.02, {0, 1});
  TurnRecordedViews(&card.obs, 0.4, 7);
  NormalSearchOptions search;
  search.enabled = true;
  search.prior = 2;
  search.min_tilt_deg = 0;  // the weights' own effect on the false tilt
  search.view_weights = false;
  const NormalErrors plain = SearchEmbossedCard(d, card, search);
  search.view_weights = true;
  const PooledModel reference =
      FitNormalReference(d.basis.View(), card.obs, PerPixel(), {}, search);
  int weighted = 0;
  for (const PooledGroup& g : reference.groups) {
    if (g.view_weight.empty()) continue;
    ++weighted;
    REQUIRE(int(g.view_weight.size()) == card.obs.views);
    const auto [low, high] = std::minmax_element(g.view_weight.begin(), g.view_weight.end());
    CHECK(*low > 0);
    CHECK(*high <= 10.0 + 1e-9);  // the floor: a tenth of the mean misfit
    CHECK(*low < 1);
    CHECK(*high > 1);
  }
  CHECK(weighted >= 1);
  const NormalErrors weights = SearchEmbossedCard(d, card, search);
  INFO("relief " << plain.relief << " -> " << weights.relief << ", flat " << plain.flat << " -> "
                 << weights.flat);
  CHECK(weights.relief < plain.relief);
  CHECK(weights.flat < plain.flat);
}

TEST_CASE("relief too steep for the search: refused, never NaN", "[normals]") {
  const Fixture& d = Data();
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(16, 16, 10.0, 2, 1);
  sim::ReliefOptions relief;
  relief.slope_deg = 45;  // beyond the 25 degree cone
  sim::SetNormalsFromHeight(&scene, sim::CardRelief(scene, relief));
  const PixelObservations observed = sim::SyntheticObservations(
      scene, {d.continuous[0], d.continuous[1]}, d.views, {}, 0, int(scene.label.size()));
  NormalSearchOptions searched;
  searched.enabled = true;
  const PooledModel reference =
      FitNormalReference(d.basis.View(), observed, PerPixel(), {}, searched);
  for (const bool mixtures : {false, true}) {
    PixelObservations obs = observed;
    NormalSearchOptions search;
    search.enabled = true;
    search.mixed_pixels = mixtures;
    const PixelNormals normals =
        EstimateNormals(d.basis.View(), &obs, PerPixel(), search, &reference);
    int steep = 0, steep_estimated = 0, steep_refused = 0;
    for (std::size_t p = 0; p < scene.label.size(); ++p) {
      REQUIRE(normals.normal[p].allFinite());
      if (normals.status[p] == NormalStatus::kRefused)
        CHECK(normals.normal[p] == Eigen::Vector3f::UnitZ());
      if (NormalAngle(scene.normal[p], Eigen::Vector3f::UnitZ()) > DegToRad(25)) {
        ++steep;
        steep_estimated += normals.status[p] == NormalStatus::kEstimated;
        steep_refused += normals.status[p] == NormalStatus::kRefused;
      }
    }
    for (float v : obs.rgb) CHECK_FALSE(std::isinf(v));
    // A steep facet is dark at the views it turns away from, views that any facet inside the
    // cone faces (SeenDarkWhereLit). Measured, of 144 pixels steeper than the cone, either
    // setting: 125 refused (flagged), 19 estimated. Before the dark views were read, the cone's
    // edge alone flagged 2 (one centre) or none (two centres mixed, which explain a steep pixel
    // at a tilt inside the cone) and 66-72 were estimated 26 degrees off.
    INFO("mixtures " << mixtures << ": " << steep_estimated << " estimated, " << steep_refused
                     << " refused of " << steep);
    REQUIRE(steep > 100);
    CHECK(steep_estimated < steep / 4);
    CHECK(steep_refused > steep / 2);
  }
}

// The embossed ink card (EmbossedInkCard) as an observation source, with `noise` (relative).
sim::SyntheticSource EmbossedInkSource(double noise) {
  sim::ObservationOptions o;
  o.noise_sigma = noise;
  return sim::SyntheticSource(EmbossedInkCard(), Data().continuous, Data().views, o);
}

// Every normal the search estimated, whatever the job did with it after.
long SearchEstimated(const ReconstructionReport& r) {
  return r.normals_estimated + r.normals_reverted + r.normals_mixed_regrouped;
}

// A pooled reconstruction of `source` through the job, options as `set` leaves them, and its map.
struct PooledRun {
  ReconstructionReport report;
  SvbrdfMap map;
};
PooledRun ReconstructPooled(sim::SyntheticSource& source,
                            const std::function<void(ReconstructionOptions*)>& set) {
  ReconstructionOptions r;
  r.method = ReconstructionMethod::kPooled;
  r.progress = false;
  set(&r);
  test::TempDir dir;
  PooledRun out{Reconstruct(Data().basis.View(), source, r, {}, dir / "m.exr"), {}};
  out.map = ReadSvbrdfMap(dir / "m.exr");
  return out;
}

TEST_CASE("pooled: a pixel no group explains keeps the sample's normal", "[normals][pooled]") {
  sim::SyntheticSource source = EmbossedInkSource(0);
  const PooledRun run =
      ReconstructPooled(source, [](ReconstructionOptions* r) { r->normals.enabled = true; });
  const ReconstructionReport& report = run.report;
  const SvbrdfMap& map = run.map;
  // The guard must have had work (else the check below says nothing): the embossed card's ink
  // edges leave pixels that no group explains (measured: 221 of 2,304, all estimated alone
  // without the guard).
  INFO("taken back " << report.normals_reverted << ", kept with the prior "
                     << report.normals_settled << ", estimated " << report.normals_estimated);
  CHECK(report.normals_reverted > 0);
  // Some are explained better tilted, and keep their normal with their group's prior.
  CHECK(report.normals_settled > 0);
  CHECK(report.normals_estimated > 0);
  int estimated_alone = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const bool estimated = map.Plane("normal_status", x, y) == float(NormalStatus::kEstimated);
      estimated_alone += estimated && map.Plane("group", x, y) < 0;
      for (float c : map.Coefficients(x, y, 0)) REQUIRE(std::isfinite(c));
    }
  CHECK(estimated_alone == 0);
}

TEST_CASE("pooled: the map's solve confirms a tilt, or it goes back to the sample's normal",
          "[normals][pooled]") {
  sim::SyntheticSource source = EmbossedInkSource(0.03);
  const sim::SyntheticSvbrdf& scene = source.scene();
  const auto run = [&](NormalConfirmation confirmation) {
    return ReconstructPooled(source, [&](ReconstructionOptions* r) {
      r->normals.enabled = true;
      r->normals.confirmation = confirmation;
    });
  };
  const PooledRun alone = run(NormalConfirmation::kAlone);
  const PooledRun regrouped = run(NormalConfirmation::kRegrouped);
  const PooledRun all = run(NormalConfirmation::kAll);
  INFO("taken back: alone " << alone.report.normals_reverted << ", regrouped "
                            << regrouped.report.normals_reverted << ", all "
                            << all.report.normals_reverted);
  // Each setting judges a superset of the one before with the same rule, so it takes back at
  // least as many; kAll must have had work, or the checks below say nothing.
  CHECK(regrouped.report.normals_reverted >= alone.report.normals_reverted);
  CHECK(all.report.normals_reverted > regrouped.report.normals_reverted);
  CHECK(SearchEstimated(all.report) == SearchEstimated(alone.report));
  // A normal taken back is the sample's, flagged as assumed, and its pixel solved as read.
  std::vector<double> relief_error;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      const auto status = NormalStatus(int(all.map.Plane("normal_status", x, y)));
      const Eigen::Vector3f n(all.map.Plane("normal.x", x, y), all.map.Plane("normal.y", x, y),
                              all.map.Plane("normal.z", x, y));
      if (status == NormalStatus::kAssumed) CHECK(n == Eigen::Vector3f::UnitZ());
      for (float c : all.map.Coefficients(x, y, 0)) REQUIRE(std::isfinite(c));
      const Eigen::Vector3f truth = scene.normal[std::size_t(y * 48 + x)];
      if (NormalAngle(truth, Eigen::Vector3f::UnitZ()) > DegToRad(0.5))
        relief_error.push_back(RadToDeg(NormalAngle(truth, n)));
    }
  // The issue's goal over the relief holds with every tilt confirmed.
  INFO("relief " << Median(relief_error));
  CHECK(Median(relief_error) < 2.0);
}

TEST_CASE("pooled: a mixed pixel's tilt keeps its group", "[normals][pooled]") {
  sim::SyntheticSource source = EmbossedInkSource(0.03);
  const auto run = [&](bool normals, bool same_group) {
    return ReconstructPooled(source, [&](ReconstructionOptions* r) {
      r->normals.enabled = normals;
      r->normals.mixed_same_group = same_group;
    });
  };
  // The model is fitted on the same sample as read whatever the normals: one model, and each
  // pixel's group flat is the search-off map's.
  const PooledRun flat = run(false, false), free = run(true, false), kept = run(true, true);
  const auto regrouped = [&](const PooledRun& tilted, int x, int y) {
    const float g = tilted.map.Plane("group", x, y), f = flat.map.Plane("group", x, y);
    return tilted.map.Plane("normal_status", x, y) == float(NormalStatus::kEstimated) && g >= 0 &&
           f >= 0 && g != f;
  };
  int regrouped_free = 0, regrouped_kept = 0, taken_back_here = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 48; ++x) {
      regrouped_free += regrouped(free, x, y);
      regrouped_kept += regrouped(kept, x, y);
      taken_back_here += free.map.Plane("normal_status", x, y) == float(NormalStatus::kEstimated) &&
                         kept.map.Plane("normal_status", x, y) == float(NormalStatus::kAssumed);
    }
  const long taken_back = kept.report.normals_mixed_regrouped;
  INFO("estimated normals in another group than flat: "
       << regrouped_free << " free, " << regrouped_kept << " kept; taken back " << taken_back);
  // The rule must have had work, or this test says nothing. The two maps differ only in the
  // pixels taken back (the solve is deterministic), each one of those regrouped; unmixed
  // pixels are not judged, so some stay regrouped. (What the rule buys is measured through
  // acqd, where a pixel's footprint straddles inks and facets: docs/reconstruction.md, "A mixed
  // pixel's tilt keeps its group". This card's pixels are each one ink on one facet, and the 72
  // it takes back predict directions no view saw about as well either way: relative RMS 0.984
  // taken back against 0.977 tilted, measured.)
  REQUIRE(taken_back > 0);
  CHECK(taken_back_here == taken_back);
  CHECK(regrouped_kept == regrouped_free - taken_back);
  // Every normal the search estimated is accounted for once.
  CHECK(SearchEstimated(kept.report) == SearchEstimated(free.report));
}

TEST_CASE("a height map integrated from the normals is the relief's", "[normals]") {
  sim::SyntheticSvbrdf scene = sim::MakeCardLayout(96, 80, 10.0, 3, 1);
  sim::ReliefOptions relief;
  relief.slope_deg = 10;
  relief.fibre_deg = 2;
  const std::vector<float> truth = sim::CardRelief(scene, relief);
  sim::SetNormalsFromHeight(&scene, truth);
  // The card's grid and the map's share one row rule (core/sample_grid.h): rows to the sample's -y.
  const std::vector<Eigen::Vector3f>& normals = scene.normal;
  const std::vector<float> height = HeightFromNormals(normals, scene.width, scene.height);
  REQUIRE(height.size() == truth.size());
  double mean_truth = 0, mean_height = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) mean_truth += truth[i], mean_height += height[i];
  mean_truth /= double(truth.size()), mean_height /= double(truth.size());
  double sxy = 0, sxx = 0, syy = 0, err2 = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const double a = truth[i] - mean_truth, b = height[i] - mean_height;
    REQUIRE(std::isfinite(b));
    sxy += a * b, sxx += a * a, syy += b * b, err2 += (a - b) * (a - b);
  }
  // Frankot-Chellappa takes the map as periodic, which costs a little near the edges; measured:
  // correlation 0.998, RMS error 0.063 of the relief's RMS. With the rows' sense wrong in one of
  // the two (n.y negated) the correlation is -0.25.
  const double correlation = sxy / std::sqrt(sxx * syy);
  INFO("correlation " << correlation << ", RMS error / RMS relief " << std::sqrt(err2 / sxx));
  CHECK(correlation > 0.95);
  CHECK(std::sqrt(err2 / sxx) < 0.35);
  CHECK_THROWS_AS(HeightFromNormals(normals, scene.width + 1, scene.height), UserError);
}

TEST_CASE("a height map of the wrong size is refused, naming both sizes", "[normals]") {
  const std::string path = std::filesystem::temp_directory_path() / "acq_height_wrong.exr";
  FloatPlanes planes;
  planes.width = 8;
  planes.height = 6;
  planes.planes["height"].assign(48, 0.0f);
  WriteFloatPlanesExr(path, planes);
  try {
    sim::ReadHeightMap(path, 16, 16, 8.0);
    FAIL("accepted");
  } catch (const UserError& e) {
    CHECK_THAT(e.what(), Catch::Contains("8x6") && Catch::Contains("16x16"));
  }
  planes.planes.clear();
  planes.planes["z"].assign(48, 0.0f);
  WriteFloatPlanesExr(path, planes);
  CHECK_THROWS_WITH(sim::ReadHeightMap(path, 8, 6, 8.0), Catch::Contains("'height'"));
  std::filesystem::remove(path);
}
