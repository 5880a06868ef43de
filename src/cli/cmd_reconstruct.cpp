#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>

#include "acq/map_score.h"
#include "acq/move_planner.h"
#include "acq/reconstruction_job.h"
#include "brdf/basis_file.h"
#include "brdf/directions.h"
#include "brdf/evaluation.h"
#include "brdf/fov_evaluation.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/geometry_args.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/facet_frame.h"
#include "sim/relief.h"
#include "sim/sample_layouts.h"
#include "sim/synthetic_svbrdf.h"

namespace acq::cli {
namespace {

bool OnOffFrom(const Args& args, const std::string& name, bool fallback) {
  const std::string v = args.Get(name, fallback ? "on" : "off");
  if (v == "on") return true;
  if (v == "off") return false;
  throw UserError("--" + name, "must be 'on' or 'off', got '" + v + "'");
}

RowLookup LookupFrom(const Args& args) {
  const std::string l = args.Get("lookup", "nearest");
  if (const std::optional<RowLookup> lookup = ParseRowLookup(l)) return *lookup;
  throw UserError("--lookup", "must be 'nearest' or 'interpolated', got '" + l + "'");
}

PixelKernel KernelFrom(const Args& args) {
  const std::string k = args.Get("kernel", "lanes");
  if (k == "lanes") return PixelKernel::kLanesDouble;
  if (k == "lanes-single") return PixelKernel::kLanesSingle;
  if (k == "one-pixel") return PixelKernel::kOnePixel;
  throw UserError("--kernel", "must be 'lanes', 'lanes-single' or 'one-pixel', got '" + k + "'");
}

ReconstructionMethod MethodFrom(const Args& args) {
  const std::string m = args.Get("method", ReconstructionMethodName(kDefaultReconstructionMethod));
  if (const std::optional<ReconstructionMethod> method = ParseReconstructionMethod(m))
    return *method;
  throw UserError("--method", "must be 'independent' or 'pooled', got '" + m + "'");
}

NormalCriterion NormalCriterionFrom(const Args& args, NormalCriterion fallback) {
  const std::string c = args.Get("normals-criterion", NormalCriterionName(fallback));
  if (const std::optional<NormalCriterion> criterion = ParseNormalCriterion(c)) return *criterion;
  throw UserError("--normals-criterion", "must be 'fit', 'held-out' or 'centre', got '" + c + "'");
}

NormalSearchMethod NormalSearchMethodFrom(const Args& args, NormalSearchMethod fallback) {
  const std::string m = args.Get("normals-search", NormalSearchMethodName(fallback));
  if (const std::optional<NormalSearchMethod> method = ParseNormalSearchMethod(m)) return *method;
  throw UserError("--normals-search", "must be 'grid' or 'quadratic', got '" + m + "'");
}

NormalConfirmation NormalConfirmationFrom(const Args& args, NormalConfirmation fallback) {
  const std::string c = args.Get("normals-confirm", NormalConfirmationName(fallback));
  if (const std::optional<NormalConfirmation> parsed = ParseNormalConfirmation(c)) return *parsed;
  throw UserError("--normals-confirm", "must be 'alone', 'regrouped' or 'all', got '" + c + "'");
}

// The sample: a built-in one (--sample) or one described in a file (--sample-labels,
// --sample-weights), whose size is then the file's.
sim::MixedSample SampleFrom(const Args& args, const std::vector<std::string>& names, int w, int h,
                            const sim::ObservationOptions& o) {
  const double size = o.geometry.sample_size_mm;
  if (args.Has("sample-labels") && args.Has("sample-weights"))
    throw UserError("--sample-labels", "give a label image or a weight image, not both");
  if (args.Has("sample-labels") || args.Has("sample-weights")) {
    const SampleFile file =
        args.Has("sample-labels")
            ? SampleFile{SampleFile::Kind::kLabels, args.Get("sample-labels")}
            : SampleFile{SampleFile::Kind::kWeights, args.Get("sample-weights")};
    sim::MixedSample from_file = sim::ReadSampleFile(file, names, size);
    if (args.Has("size") && (from_file.layout.width != w || from_file.layout.height != h))
      throw UserError(file.path,
                      "the sample file is " + std::to_string(from_file.layout.width) + "x" +
                          std::to_string(from_file.layout.height) + " pixels but --size says " +
                          args.Get("size"),
                      "leave out --size: the file's size is used");
    return from_file;
  }
  const std::string kind = args.Get("sample", "card");
  const std::optional<SampleKind> k = ParseSampleKind(kind);
  if (!k) throw UserError("--sample", "must be card, blend, marble or text, got '" + kind + "'");
  return sim::MakeSample(*k, w, h, size, int(names.size()), o.seed);
}

void ParseSize(const std::string& s, int* w, int* h) {
  char rest = 0;
  if (std::sscanf(s.c_str(), "%dx%d%c", w, h, &rest) != 2 || *w < 1 || *h < 1 || *w > 16384 ||
      *h > 16384)
    throw UserError("--size", "expected WIDTHxHEIGHT in pixels (1 to 16384 each), got '" + s + "'",
                    "e.g. --size 256x256");
  // The map's planes and the observations of a band: 64 megapixels is 4 x the instrument's
  // largest sensor, and about 20 GB of map planes, this machine's memory.
  if (double(*w) * double(*h) > 64e6)
    throw UserError("--size", s + " is over 64 megapixels", "reconstruct a smaller card");
}

}  // namespace

// The relief the options ask for (--relief-deg: the built-in embossing; --height-map: a file),
// as the scene's true normals.
void AddRelief(const Args& args, sim::SyntheticSvbrdf* layout) {
  if (args.Has("relief-deg") && args.Has("height-map"))
    throw UserError("--height-map", "give --relief-deg or --height-map, not both");
  std::vector<float> height;
  if (args.Has("height-map")) {
    height = sim::ReadHeightMap(args.Get("height-map"), layout->width, layout->height,
                                sim::kPngHeightFullScalePx);
  } else if (args.Has("relief-deg") || args.Has("fibre-deg")) {
    sim::ReliefOptions relief;
    relief.slope_deg = args.GetDouble("relief-deg", 0, 0, 59.9);
    relief.fibre_deg = args.GetDouble("fibre-deg", 0, 0, 29.9);
    relief.seed = std::uint64_t(args.GetInt("seed", 1));
    height = sim::CardRelief(*layout, relief);
  } else {
    return;
  }
  sim::SetNormalsFromHeight(layout, height);
}

// The recovered normals against the scene's (acq/map_score.h).
void PrintNormalScore(const SvbrdfMap& map, const sim::SyntheticSvbrdf& scene) {
  const NormalScore n =
      ScoreNormals(map, scene.normal, std::vector<int>(scene.label.begin(), scene.label.end()));
  std::printf(
      "score: normals: median angular error %.3f deg over the relief (%ld pixels; %.3f assumed "
      "flat; %.3f over %ld of one material, %.3f over %ld at ink edges), median false tilt %.3f "
      "deg on flat areas (%ld pixels), %ld refused, %ld without evidence\n",
      n.median_error_deg_relief, n.relief_pixels, n.median_error_deg_relief_assumed_flat,
      n.median_error_deg_relief_one_material, n.relief_pixels_one_material,
      n.median_error_deg_relief_ink_edges, n.relief_pixels_ink_edges, n.median_tilt_deg_flat,
      n.flat_pixels, n.refused, n.no_evidence);
  std::printf(
      "score: normals' uncertainty: median %.3f deg over the estimated pixels; relief error %.3f "
      "deg median where %.0f deg or less (%ld pixels), %.3f where more (%ld)\n",
      n.median_uncertainty_deg, n.median_error_deg_relief_certain, kCertainNormalDeg,
      n.relief_pixels_certain, n.median_error_deg_relief_uncertain, n.relief_pixels_uncertain);
}

int ReconstructSynthetic(const Argv& argv) {
  std::set<std::string> valued = {"basis",
                                  "directions",
                                  "materials",
                                  "materials-dir",
                                  "size",
                                  "k",
                                  "eta",
                                  "lookup",
                                  "band-rows",
                                  "noise",
                                  "seed",
                                  "o",
                                  "min-observations",
                                  "max-condition",
                                  "dump",
                                  "row-tile",
                                  "kernel",
                                  "method",
                                  "groups",
                                  "max-groups",
                                  "design-sigma-deg",
                                  "sample-pixels",
                                  "sample",
                                  "sample-labels",
                                  "sample-weights",
                                  "relief-deg",
                                  "fibre-deg",
                                  "height-map",
                                  "normals-max-tilt-deg",
                                  "normals-prior",
                                  "normals-k",
                                  "normals-criterion",
                                  "normals-score-min-cos",
                                  "normals-evidence",
                                  "normals-min-tilt-deg",
                                  "normals-view-weights",
                                  "normals-mixed-same-group",
                                  "normals-same-centre",
                                  "normals-estimated-min-cos",
                                  "normals-trimmed-views",
                                  "normals-max-uncertainty-deg",
                                  "normals-confirm",
                                  "normals-search",
                                  "normals-levels",
                                  "normals-coarse-reach"};
  valued.insert(kGeometryOptions.begin(), kGeometryOptions.end());
  const Args args("acq reconstruct synthetic", argv, valued,
                  {"ignore-near-field", "truth-tables", "score", "quiet", "normals",
                   "normals-single-centre", "spread-half-vectors"});
  const std::string basis_path = args.Required("basis"), out = args.Required("o");
  // The options that are numbers, checked before any file is read.
  int w = 0, h = 0;
  ParseSize(args.Get("size", "256x256"), &w, &h);
  const double noise = args.GetDouble("noise", 0.0, 0, 10);
  const MappedBasis mapped = MappedBasis::Open(basis_path);
  const BasisView& basis = mapped.View();
  const std::vector<Direction> directions = ReadDirectionsTsv(args.Required("directions"));
  // Each view at phi_h = 0, or as a capture with gantry.half_vector_azimuths: spread plans it.
  const std::vector<double> phi_h =
      args.Has("spread-half-vectors")
          ? SpreadHalfVectorAzimuths(directions, GantryMotion{}.phi_h_steps)
          : std::vector<double>(directions.size(), 0.0);
  std::vector<ArmAngles> views;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    RusinkiewiczAngles angles = directions[i].angles;
    angles.phi_h = phi_h[i];
    views.push_back(ArmAnglesFor(angles));
  }

  // The card's inks: named materials (default: four of the issue-2 held-out set).
  const std::string dir = args.Get("materials-dir", "data/nbrdf/merl");
  std::vector<std::string> names = args.All("materials");
  if (names.empty()) names = {"white-paint", "brass", "black-fabric", "pink-jasper"};
  if (names.size() > 255) throw UserError("--materials", "at most 255 materials");
  std::vector<NeuralBrdf> networks;
  std::vector<MerlBrdf> tables;
  for (const std::string& n : names) {
    const std::string path = dir + "/" + n + ".h5";
    if (!std::filesystem::exists(path))
      throw UserError(path, "no neural-BRDF fit of that name", "see " + dir + " for the names");
    networks.push_back(NeuralBrdf::Load(path));
  }
  const bool need_tables = args.Has("truth-tables") || args.Has("score");
  if (need_tables)
    for (const auto& n : networks) tables.push_back(n.Tabulate());
  std::vector<sim::GroundTruth> base;
  for (std::size_t i = 0; i < networks.size(); ++i)
    base.push_back({&networks[i], args.Has("truth-tables") ? &tables[i] : nullptr});

  const std::vector<NearFieldGeometry> geometries = GeometriesFrom(args);
  if (geometries.size() != 1) throw UserError("--fov-deg", "give one field of view");
  sim::ObservationOptions o;
  o.geometry = geometries[0];
  o.centre_directions = args.Has("ignore-near-field");
  o.noise_sigma = noise;
  o.seed = std::uint64_t(args.GetInt("seed", 1));
  sim::MixedSample sample = SampleFrom(args, names, w, h, o);
  AddRelief(args, &sample.layout);
  const std::vector<sim::GroundTruth> truth = sample.Truths(base);
  sim::SyntheticSource source(sample.layout, truth, views, o);
  w = sample.layout.width, h = sample.layout.height;

  ReconstructionOptions r;
  r.solve.components = args.GetInt("k", r.solve.components, 1, 64);
  r.solve.eta = args.GetDouble("eta", r.solve.eta, 0, 1e12);
  r.solve.lookup = LookupFrom(args);
  r.solve.min_observations = args.GetInt("min-observations", 0, 0, 10000);
  r.solve.max_condition = args.GetDouble("max-condition", r.solve.max_condition);
  r.band_rows = args.GetInt("band-rows", r.band_rows, 1, 1 << 20);
  r.solve.row_tile = args.GetInt("row-tile", r.solve.row_tile, 1, 4096);
  r.solve.kernel = KernelFrom(args);
  r.method = MethodFrom(args);
  r.pooled.groups = args.GetInt("groups", 0, 0, 1024);
  r.pooled.max_groups = args.GetInt("max-groups", r.pooled.max_groups, 1, 1024);
  r.pooled.sample_pixels = args.GetInt("sample-pixels", r.pooled.sample_pixels, 64, 1 << 20);
  r.pooled.design_sigma_deg =
      args.GetDouble("design-sigma-deg", r.pooled.design_sigma_deg, 0, kMaxDesignSigmaDeg);
  r.pooled.seed = o.seed;
  r.normals.enabled = args.Has("normals");
  r.normals.mixed_pixels = !args.Has("normals-single-centre");
  r.normals.view_weights = OnOffFrom(args, "normals-view-weights", r.normals.view_weights);
  r.normals.same_centre = OnOffFrom(args, "normals-same-centre", r.normals.same_centre);
  r.normals.mixed_same_group =
      OnOffFrom(args, "normals-mixed-same-group", r.normals.mixed_same_group);
  r.normals.trimmed_views =
      args.GetInt("normals-trimmed-views", r.normals.trimmed_views, 0, kMaxNormalsTrimmedViews);
  r.normals.max_uncertainty_deg =
      args.GetDouble("normals-max-uncertainty-deg", r.normals.max_uncertainty_deg, 0, 90);
  r.normals.max_tilt_deg = args.GetDouble("normals-max-tilt-deg", r.normals.max_tilt_deg, 1, 59);
  r.normals.prior = args.GetDouble("normals-prior", r.normals.prior, 0, 1e6);
  r.normals.components = args.GetInt("normals-k", r.normals.components, 1, 64);
  r.normals.criterion = NormalCriterionFrom(args, r.normals.criterion);
  r.normals.evidence = args.GetDouble("normals-evidence", r.normals.evidence, 0, 1e6);
  r.normals.min_tilt_deg = args.GetDouble("normals-min-tilt-deg", r.normals.min_tilt_deg, 0, 59);
  r.normals.estimated_min_cos =
      args.GetDouble("normals-estimated-min-cos", r.normals.estimated_min_cos, 0, 0.9);
  r.normals.score_min_cos =
      args.GetDouble("normals-score-min-cos", r.normals.score_min_cos, 0, 0.9);
  r.normals.method = NormalSearchMethodFrom(args, r.normals.method);
  r.normals.confirmation = NormalConfirmationFrom(args, r.normals.confirmation);
  r.normals.levels = args.GetInt("normals-levels", r.normals.levels, 0, 12);
  r.normals.coarse_reach = args.GetInt("normals-coarse-reach", r.normals.coarse_reach, 1, 4);
  r.progress = !args.Has("quiet");
  SvbrdfMapInfo info;
  info.basis = basis_path;
  info.basis_crc32 = mapped.Checksum();
  info.camera_model = kSyntheticCameraModel;
  const ReconstructionReport report = Reconstruct(basis, source, r, info, out);
  std::printf("map: %s (%dx%d, k = %d, %s rows)\n", out.c_str(), w, h, r.solve.components,
              args.Get("lookup", "nearest").c_str());
  report.Print();

  if (args.Has("dump")) {
    // For benchmarks against other implementations: the exact observations and our result, as
    // raw little-endian float32 (light, camera: pixels x views x 3; rgb: pixels x views x 3;
    // coefficients: pixels x 3 x k), and their sizes in dump.txt.
    const std::string dir = args.Get("dump");
    std::filesystem::create_directories(dir);
    const PixelObservations all = source.Rows(0, h);
    auto write = [&](const std::string& name, const void* data, std::size_t bytes) {
      std::FILE* f = std::fopen((dir + "/" + name).c_str(), "wb");
      if (!f || std::fwrite(data, 1, bytes, f) != bytes)
        throw UserError(dir + "/" + name, "cannot write", "check free disk space");
      std::fclose(f);
    };
    write("light.f32", all.light.data(), all.light.size() * sizeof(Eigen::Vector3f));
    write("camera.f32", all.camera.data(), all.camera.size() * sizeof(Eigen::Vector3f));
    write("rgb.f32", all.rgb.data(), all.rgb.size() * sizeof(float));
    const SvbrdfMap map = ReadSvbrdfMap(out);
    std::vector<float> coefficients;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const auto v = map.Coefficients(x, y, c);
          coefficients.insert(coefficients.end(), v.begin(), v.end());
        }
    write("coefficients.f32", coefficients.data(), coefficients.size() * sizeof(float));
    const std::string meta =
        "pixels " + std::to_string(all.pixels) + "\nviews " + std::to_string(all.views) + "\nk " +
        std::to_string(r.solve.components) + "\neta " + std::to_string(r.solve.eta) +
        "\nsolve_seconds " + std::to_string(report.solve_seconds) + "\n";
    write("dump.txt", meta.data(), meta.size());
  }

  if (args.Has("score")) {
    // Against the ground truth: each pixel's grid log-space RMSE against its material's table.
    const SvbrdfMap map = ReadSvbrdfMap(out);
    const std::vector<std::uint8_t>& labels = source.scene().label;
    const std::vector<MerlBrdf> mixed = sample.Tables(tables);
    const std::vector<std::string> sample_names = sample.Names(names);
    const MapScore score =
        ScoreMap(map, basis, std::vector<int>(labels.begin(), labels.end()), mixed);
    std::printf(
        "score: median per-pixel log-space RMSE against the ground truth: %.4f (%ld pixels x 3 "
        "channels; %.4f over the %ld valid)\n",
        score.median_log_rmse, score.pixels, score.median_log_rmse_valid, score.valid);
    // Which groups each material's pixels went to (the pooled reconstruction's diagnostics).
    std::vector<std::map<int, long>> groups(sample_names.size());
    for (std::size_t p = 0; p < labels.size(); ++p)
      ++groups[labels[p]][int(map.Plane("group", int(p) % w, int(p) / w))];
    for (std::size_t m = 0; m < sample_names.size(); ++m) {
      std::string in;
      for (const auto& [g, n] : groups[m])
        in += " " + (g < 0 ? std::string("alone") : "g" + std::to_string(g)) + ":" +
              std::to_string(n);
      std::printf(
          "score: material %s median per-pixel log-space RMSE %.4f; diffuse colour CIEDE2000 "
          "%.2f (its mean colour's %.2f);%s\n",
          sample_names[m].c_str(), score.material_median_log_rmse[m],
          score.material_albedo_delta_e2000_median[m], score.material_albedo_mean_delta_e2000[m],
          in.c_str());
    }
    if (!source.scene().normal.empty()) PrintNormalScore(map, source.scene());
  }
  return 0;
}

}  // namespace acq::cli
