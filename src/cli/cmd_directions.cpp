#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "acq/move_planner.h"
#include "brdf/basis_file.h"
#include "brdf/direction_optimizer.h"
#include "brdf/directions.h"
#include "brdf/evaluation.h"
#include "brdf/fov_evaluation.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/geometry_args.h"
#include "cli/held_out.h"
#include "core/angles.h"
#include "core/error.h"

namespace acq::cli {
namespace {

// A CSV field, quoted when it holds a comma, quote or newline (RFC 4180).
std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::set<std::string> With(std::set<std::string> a, const std::set<std::string>& b) {
  a.insert(b.begin(), b.end());
  return a;
}

}  // namespace

int DirectionsRandom(const Argv& argv) {
  const Args args("acq directions random", argv, {"n", "seed", "o"}, {});
  const int n = args.GetInt("n", 20, 1, 100000);
  const int seed = args.GetInt("seed", 1, 0, INT_MAX);
  const std::string out = args.Required("o");
  WriteDirectionsTsv(RandomDirections(n, std::uint64_t(seed)), out,
                     std::to_string(n) +
                         " random directions (light and camera uniform over the "
                         "hemisphere), seed " +
                         std::to_string(seed) + "; Rusinkiewicz, degrees");
  std::printf("wrote %d directions to %s\n", n, out.c_str());
  return 0;
}

int DirectionsOptimize(const Argv& argv) {
  const Args args("acq directions optimize", argv,
                  With(With({"basis", "n", "k", "seed", "candidates", "o", "fov-grid",
                             "fov-objective", "score", "eta", "max-condition"},
                            kConstraintOptions),
                       kGeometryOptions),
                  {"unconstrained", "quiet"});
  const std::string basis_path = args.Required("basis");
  const std::string out = args.Required("o");
  const MappedBasis mapped = MappedBasis::Open(basis_path);
  OptimizerOptions o;
  o.n = args.GetInt("n", o.n, 1, 1000);
  o.k = args.GetInt("k", 0, 0, 1024);
  o.seed = std::uint64_t(args.GetInt("seed", 1));
  o.candidates = args.GetInt("candidates", o.candidates, 1, 10000000);
  o.constraints = ConstraintsFrom(args);
  o.fov_grid = args.GetInt("fov-grid", o.fov_grid, 1, 100);
  o.progress = !args.Has("quiet");
  const std::vector<NearFieldGeometry> geometries = GeometriesFrom(args);
  if (geometries.size() != 1)
    throw UserError("--fov-deg", "optimise for one field of view at a time");
  o.geometry = geometries[0];
  const std::string objective = args.Get("fov-objective", "worst");
  if (objective != "worst" && objective != "mean")
    throw UserError("--fov-objective", "must be 'worst' or 'mean', got '" + objective + "'");
  o.fov_objective = objective == "worst" ? FovObjective::kWorst : FovObjective::kMean;
  const std::string score = args.Get("score", "expected-error");
  if (score != "condition" && score != "expected-error")
    throw UserError("--score", "must be 'condition' or 'expected-error', got '" + score + "'");
  o.score = score == "condition" ? Score::kCondition : Score::kExpectedError;
  o.eta = args.GetDouble("eta", o.eta, 0, 1e12);
  o.max_condition = args.GetDouble("max-condition", o.max_condition, 1, 1e300);
  if (!(o.max_condition > 1)) throw UserError("--max-condition", "must be greater than 1");

  const OptimizedDirections result = OptimizeDirections(mapped.View(), o);
  for (const Direction& d : result.directions) {
    const std::string why = o.constraints.Violation(ArmAnglesFor(d.angles));
    if (!why.empty()) throw std::logic_error("optimiser returned a disallowed direction: " + why);
  }
  char comment[512];
  std::snprintf(
      comment, sizeof comment,
      "%d directions optimised by acq directions optimize on %s\n"
      "k = %d, seed %llu, %d candidates; constraints: %s\n"
      "field of view %.2f deg (%s objective); condition number %.6g\n"
      "Rusinkiewicz angles in degrees, then arm angles for phi_h = 0 (camera on the "
      "smaller zenith)",
      o.n, basis_path.c_str(), o.EffectiveK(), (unsigned long long)o.seed, o.candidates,
      o.constraints.enabled
          ? ("camera zenith <= " + std::to_string(RadToDeg(o.constraints.max_camera_zenith)) +
             ", light zenith <= " + std::to_string(RadToDeg(o.constraints.max_light_zenith)) +
             ", separation >= " + std::to_string(RadToDeg(o.constraints.min_separation)))
                .c_str()
          : "above the horizon only",
      FovDeg(o.geometry), objective.c_str(), result.condition);
  WriteDirectionsTsv(result.directions, out, comment);
  std::printf(
      "optimised %d directions in %.1f s: condition number %.4g (k = %d%s)\nwrote %s\n", o.n,
      result.seconds, result.condition, o.EffectiveK(),
      o.geometry.sample_size_mm > 0 ? (", " + objective + " over the field of view").c_str() : "",
      out.c_str());
  return 0;
}

int DirectionsEval(const Argv& argv) {
  const Args args("acq directions eval", argv,
                  With({"basis", "directions", "k", "eta", "noise", "noise-trials", "grid", "csv",
                        "label", "seed"},
                       kGeometryOptions),
                  {"all-given", "ignore-near-field"});
  const std::string basis_path = args.Required("basis");
  const MappedBasis mapped = MappedBasis::Open(basis_path);
  const BasisView& basis = mapped.View();
  const std::string directions_path = args.Required("directions");
  const std::vector<Direction> directions = ReadDirectionsTsv(directions_path);
  FovEvalOptions o;
  o.ridge.components = args.GetInt("k", int(directions.size()), 1, 1024);
  o.ridge.eta = args.GetDouble("eta", o.ridge.eta, 0, 1e12);
  o.ridge.Check(basis);
  o.grid = args.GetInt("grid", o.grid, 1, 1000);
  if (o.grid < 1) throw UserError("--grid", "must be at least 1");
  o.ignore_near_field = args.Has("ignore-near-field");
  o.noise_trials = args.GetInt("noise-trials", o.noise_trials, 1, 100000);
  o.seed = std::uint64_t(args.GetInt("seed", 1));
  std::vector<double> noise_levels;
  for (const std::string& s :
       args.Has("noise") ? args.All("noise") : std::vector<std::string>{"0"}) {
    try {
      noise_levels.push_back(std::stod(s));
    } catch (const std::exception&) {
      throw UserError("--noise", "expected numbers, got '" + s + "'");
    }
    if (!(noise_levels.back() >= 0 && noise_levels.back() <= 10))
      throw UserError("--noise", "must be from 0 to 10 (a relative noise level)");
  }

  std::vector<MerlBrdf> truths;
  const auto materials = SelectHeldOut(basis, basis_path, args, "acq directions eval");
  truths.resize(materials.size());
  for (std::size_t i = 0; i < materials.size(); ++i) truths[i] = LoadMaterial(materials[i]);
  const HeldOutSet held_out(basis, truths);

  const std::string csv_path = args.Get("csv");
  std::ofstream csv;
  if (!csv_path.empty()) {
    const bool fresh = !std::filesystem::exists(csv_path);
    csv.open(csv_path, std::ios::app);
    if (!csv) throw UserError(csv_path, "cannot write file");
    if (fresh)
      csv << "label,directions,n,k,eta,fov_deg,sample_size_mm,positions,ignore_near_field,"
             "noise_sigma,condition_centre,condition_median,condition_worst,noise_gain,"
             "median_log_rmse,median_worst_position_log_rmse\n";
  }
  std::printf("directions %s (n = %zu), k = %d, eta = %g, %zu held-out materials\n",
              directions_path.c_str(), directions.size(), o.ridge.components, o.ridge.eta,
              materials.size());
  std::printf("%8s %9s %6s %8s %11s %11s %11s %8s %10s %10s\n", "fov_deg", "sample_mm", "noise",
              "positions", "cond_centre", "cond_median", "cond_worst", "gain", "log_rmse",
              "worst_pos");
  bool warned = false;
  for (const NearFieldGeometry& g : GeometriesFrom(args)) {
    for (double sigma : noise_levels) {
      o.geometry = g;
      o.noise_sigma = sigma;
      const FovResult r = EvaluateOverFov(held_out, directions, o);
      const double median = Median(r.channel_log_rmse);
      const double worst = Median(r.channel_worst_log_rmse);
      std::printf("%8.2f %9.1f %6.3f %8d %11.4g %11.4g %11.4g %8.3f %10.4f %10.4f\n", FovDeg(g),
                  g.sample_size_mm, sigma, r.positions, r.condition_centre, r.condition_median,
                  r.condition_worst, r.noise_gain, median, worst);
      if (csv.is_open())
        csv << CsvField(args.Get("label", directions_path)) << "," << CsvField(directions_path)
            << "," << directions.size() << "," << o.ridge.components << "," << o.ridge.eta << ","
            << FovDeg(g) << "," << g.sample_size_mm << "," << r.positions << ","
            << o.ignore_near_field << "," << sigma << "," << r.condition_centre << ","
            << r.condition_median << "," << r.condition_worst << "," << r.noise_gain << ","
            << median << "," << worst << "\n";
      if (!warned && (!(r.condition_worst < kConditionWarning) || r.noise_gain > 1.0)) {
        warned = true;
        std::fprintf(stderr,
                     "warning: condition number up to %.3g (limit %.0f) and noise gain %.2f: %s; "
                     "use more or better-spread directions, fewer components (--k) or a larger "
                     "--eta\n",
                     r.condition_worst, kConditionWarning, r.noise_gain,
                     int(directions.size()) < o.ridge.components
                         ? "fewer directions than components (n < k), the system is underdetermined"
                         : "the directions do not pin down the coefficients and observation noise "
                           "is amplified");
      }
    }
  }
  return 0;
}

int DirectionsPlan(const Argv& argv) {
  const Args args(
      "acq directions plan", argv,
      With({"directions", "o", "theta-speed-deg-s", "theta-accel-deg-s2", "phi-speed-deg-s",
            "phi-accel-deg-s2", "settle-s", "azimuth-steps", "half-vector-azimuths"},
           kConstraintOptions),
      {});
  const std::vector<Direction> directions = ReadDirectionsTsv(args.Required("directions"));
  GantryMotion m;
  m.ReadAxes([&](std::string name, double fallback) {
    std::replace(name.begin(), name.end(), '_', '-');
    return args.GetDouble(name, fallback);
  });
  m.phi_h_steps = args.GetInt("azimuth-steps", m.phi_h_steps, 1, 3600);
  m.constraints = ConstraintsFrom(args);
  m.Check();
  // Checked before any planning, which takes seconds.
  const std::string chosen = args.Get("half-vector-azimuths", "fastest");
  const std::optional<HalfVectorAzimuths> azimuths_chosen = HalfVectorAzimuthsNamed(chosen);
  if (!azimuths_chosen)
    throw UserError("--half-vector-azimuths",
                    "must be 'fastest' or 'spread', got '" + chosen + "'");

  const VisitPlan naive = PlanInFileOrder(directions, m);
  std::vector<std::size_t> file_order(directions.size());
  for (std::size_t i = 0; i < file_order.size(); ++i) file_order[i] = i;
  const VisitPlan azimuths = PlanBestAzimuths(directions, file_order, m);
  const VisitPlan fastest = PlanShortest(directions, m);
  GantryMotion spread_motion = m;
  spread_motion.half_vector_azimuths = HalfVectorAzimuths::kSpread;
  const VisitPlan spread = PlanShortest(directions, spread_motion);
  const VisitPlan& best = *azimuths_chosen == HalfVectorAzimuths::kSpread ? spread : fastest;

  std::printf("visiting order (from home: light %g/%g, camera %g/%g deg):\n",
              RadToDeg(m.home.light_theta), RadToDeg(m.home.light_phi),
              RadToDeg(m.home.camera_theta), RadToDeg(m.home.camera_phi));
  std::printf("%4s  %-28s %9s %9s %9s %9s %8s\n", "step", "direction", "light_th", "light_ph",
              "cam_th", "cam_ph", "move_s");
  for (std::size_t i = 0; i < best.poses.size(); ++i) {
    const PlannedPose& p = best.poses[i];
    std::printf("%4zu  %-28s %9.2f %9.2f %9.2f %9.2f %8.2f\n", i + 1,
                directions[p.index].where.c_str(), RadToDeg(p.arms.light_theta),
                RadToDeg(p.arms.light_phi), RadToDeg(p.arms.camera_theta),
                RadToDeg(p.arms.camera_phi), p.move_s);
  }
  std::printf("\n%-44s %8s %8s\n", "plan", "total_s", "saving");
  auto row = [&](const char* name, const VisitPlan& p) {
    std::printf("%-44s %8.1f %7.1f%%\n", name, p.total_s,
                100.0 * (1.0 - p.total_s / naive.total_s));
  };
  row("file order, phi_h = 0", naive);
  row("file order, best azimuths", azimuths);
  row("shortest order found, best azimuths", fastest);
  const std::string spread_row = spread.spread_tolerance_deg > 0
                                     ? "shortest order found, spread within " +
                                           DegString(DegToRad(spread.spread_tolerance_deg), 0) +
                                           " deg"
                                     : "half vectors spread: no safe route, fastest";
  row(spread_row.c_str(), spread);
  // What a relief's normals see of it (move_planner.h): tilts up to the seed's 15 degrees.
  const double tilt = DegToRad(kReliefTiltDeg);
  std::printf(
      "\nwidest gap between a facet tilted up to %.0f deg and the nearest half vector: fastest "
      "%.1f deg, spread %.1f deg\n",
      kReliefTiltDeg, RadToDeg(WidestHalfVectorGap(fastest, tilt)),
      RadToDeg(WidestHalfVectorGap(spread, tilt)));
  if (args.Has("o")) {
    std::ofstream f(args.Get("o"));
    if (!f) throw UserError(args.Get("o"), "cannot create file");
    f << "# visiting order from acq directions plan; total " << best.total_s << " s\n"
      << "step\tsource\tlight_theta_deg\tlight_phi_deg\tcamera_theta_deg\tcamera_phi_deg\tmove_s\n";
    for (std::size_t i = 0; i < best.poses.size(); ++i) {
      const PlannedPose& p = best.poses[i];
      f << i + 1 << "\t" << directions[p.index].where << "\t" << RadToDeg(p.arms.light_theta)
        << "\t" << RadToDeg(p.arms.light_phi) << "\t" << RadToDeg(p.arms.camera_theta) << "\t"
        << RadToDeg(p.arms.camera_phi) << "\t" << p.move_s << "\n";
    }
  }
  return 0;
}

}  // namespace acq::cli
