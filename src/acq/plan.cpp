#include "acq/plan.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <set>

#include "brdf/basis_file.h"
#include "brdf/direction_optimizer.h"
#include "core/angles.h"
#include "core/error.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

// "plan.yaml:12:5": where an error in the file is, 1-based.
std::string Place(const std::string& file, const YAML::Mark& m) {
  return file + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

// A YAML mapping with what the plan allows in it; every access checks type and names the place.
class Section {
 public:
  // `fallback` is where a section absent from the file is reported (its parent's place).
  Section(const YAML::Node& node, std::string file, std::string name, std::set<std::string> keys,
          YAML::Mark fallback = YAML::Mark())
      : node_(node),
        file_(std::move(file)),
        name_(std::move(name)),
        keys_(std::move(keys)),
        fallback_(fallback) {
    if (!node_.IsMap())
      throw UserError(Where(node_), (name_.empty() ? "the plan" : name_) + " must be a mapping",
                      "write it as `key: value` lines (docs/session-and-plan.md)");
    std::set<std::string> seen;
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar())
        throw UserError(Where(kv.first), "a key must be a name, not a list or map",
                        "write it as `key: value` lines (docs/session-and-plan.md)");
      const std::string key = kv.first.as<std::string>();
      if (!seen.insert(key).second)
        throw UserError(Where(kv.first), "'" + Qualified(key) + "' is given twice",
                        "keep one of them: which one was meant cannot be guessed");
      if (!keys_.count(key)) {
        std::string known;
        for (const std::string& k : keys_) known += (known.empty() ? "" : ", ") + k;
        throw UserError(Where(kv.first), "unknown key '" + Qualified(key) + "'",
                        "the keys here are: " + known + " (a misspelling?)");
      }
    }
  }

  bool Has(const std::string& key) const { return bool(node_[key]); }
  std::string Where(const YAML::Node& n) const {
    YAML::Mark m = n.Mark();
    if (m.is_null()) m = fallback_;  // a node made here, not read from the file
    if (m.is_null()) m.line = m.column = 0;
    return Place(file_, m);
  }
  std::string Where(const std::string& key) const {
    return Has(key) ? Where(node_[key]) : Where(node_);
  }
  std::string Qualified(const std::string& key) const {
    return name_.empty() ? key : name_ + "." + key;
  }

  template <class T>
  T Get(const std::string& key, const T& fallback, const char* type_name) const {
    const YAML::Node n = node_[key];
    if (!n) return fallback;
    try {
      if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "not a scalar");
      return n.as<T>();
    } catch (const YAML::Exception&) {
      throw UserError(Where(n), Qualified(key) + " must be " + type_name + ", not '" +
                                    (n.IsScalar() ? n.Scalar() : std::string("a list or map")) +
                                    "'");
    }
  }
  // Every number of the plan is finite (.nan, .inf and 1e999 are refused here, in one place).
  double Number(const std::string& key, double fallback) const {
    const double v = Get<double>(key, fallback, "a number");
    if (!std::isfinite(v))
      throw UserError(Where(key), Qualified(key) + " must be a finite number, not '" +
                                      node_[key].Scalar() + "'");
    return v;
  }
  // A whole number in [lo, hi], checked before any narrowing conversion.
  long long Integer(const std::string& key, long long fallback, long long lo = INT_MIN,
                    long long hi = INT_MAX) const {
    const long long v = Get<long long>(key, fallback, "a whole number");
    if (v < lo || v > hi)
      throw UserError(Where(key), Qualified(key) + " is " + std::to_string(v) + ", outside " +
                                      std::to_string(lo) + " to " + std::to_string(hi));
    return v;
  }
  std::string Text(const std::string& key, const std::string& fallback = {}) const {
    return Get<std::string>(key, fallback, "text");
  }
  bool Flag(const std::string& key, bool fallback) const {
    return Get<bool>(key, fallback, "true or false");
  }
  std::string Required(const std::string& key) const {
    if (!Has(key))
      throw UserError(Where(node_), "missing '" + Qualified(key) + "'",
                      "add it (docs/session-and-plan.md; examples/ has annotated plans)");
    return Text(key);
  }
  std::vector<double> Numbers(const std::string& key) const {
    const YAML::Node n = node_[key];
    if (!n) return {};
    if (!n.IsSequence())
      throw UserError(Where(n), Qualified(key) + " must be a list of numbers, like [1000, 8000]");
    std::vector<double> out;
    for (const YAML::Node& e : n) {
      try {
        if (!e.IsScalar()) throw YAML::Exception(e.Mark(), "not a scalar");
        out.push_back(e.as<double>());
      } catch (const YAML::Exception&) {
        throw UserError(Where(e), Qualified(key) + " must hold numbers, not '" +
                                      (e.IsScalar() ? e.Scalar() : std::string("a list or map")) +
                                      "'");
      }
      if (!std::isfinite(out.back()))
        throw UserError(Where(e),
                        Qualified(key) + " must hold finite numbers, not '" + e.Scalar() + "'");
    }
    return out;
  }
  // A list of whole numbers (counts), each in [lo, hi].
  std::vector<int> Counts(const std::string& key, int lo, int hi) const {
    std::vector<int> out;
    const YAML::Node n = node_[key];
    std::size_t i = 0;
    for (double v : Numbers(key)) {
      if (v != std::floor(v) || v < lo || v > hi)
        throw UserError(Where(n[i]), Qualified(key) + " must hold whole numbers from " +
                                         std::to_string(lo) + " to " + std::to_string(hi) +
                                         ", not " + n[i].Scalar());
      out.push_back(int(v));
      ++i;
    }
    return out;
  }
  Section Child(const std::string& key, std::set<std::string> keys) const {
    const YAML::Node n = node_[key];
    YAML::Mark here = node_.Mark();
    if (here.is_null()) here = fallback_;
    return Section(n ? n : YAML::Node(YAML::NodeType::Map), file_, Qualified(key), std::move(keys),
                   here);
  }
  // Runs `check`; a UserError it throws is re-thrown at this key's place.
  void At(const std::string& key, const std::function<void()>& check) const {
    try {
      check();
    } catch (const UserError& e) {
      throw UserError(Where(key), Qualified(key) + ": " + e.problem(), e.fix());
    }
  }

 private:
  YAML::Node node_;
  std::string file_, name_;
  std::set<std::string> keys_;
  YAML::Mark fallback_;
};

// The plan's one YAML document. A FIFO, a device or a folder is refused before it is read (a
// FIFO would block the read); a second document is refused (which was meant cannot be told).
YAML::Node LoadPlanDocument(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw UserError(path, "cannot read the plan: no such file", "check the path");
  if (!fs::is_regular_file(path, ec))
    throw UserError(path, "the plan is not a regular file (a folder, a FIFO or a device)",
                    "give the path of a plan .yaml file");
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAllFromFile(path);
  } catch (const YAML::BadFile&) {
    throw UserError(path, "cannot read the plan", "check the path and its permissions");
  } catch (const YAML::ParserException& e) {
    throw UserError(Place(path, e.mark), "not valid YAML: " + e.msg,
                    "check the indentation and the brackets there");
  }
  if (documents.empty() || documents.front().IsNull())
    throw UserError(path + ":1:1", "the plan is empty",
                    "start from an example plan (examples/plan-sim.yaml)");
  if (documents.size() > 1)
    throw UserError(Place(path, documents[1].Mark()), "a second YAML document ('---') in the plan",
                    "a plan is one document: remove the second, or give it its own file");
  return documents.front();
}

std::string Resolve(const std::string& plan_path, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  return (fs::path(plan_path).parent_path() / p).lexically_normal().string();
}

void RequireFile(const Section& s, const std::string& key, const std::string& path,
                 const std::string& fix) {
  if (!fs::is_regular_file(path))
    throw UserError(s.Where(key), s.Qualified(key) + ": no such file " + path, fix);
}

}  // namespace

const char* BackendName(Backend b) {
  switch (b) {
    case Backend::kSim:
      return "sim";
    case Backend::kUsbAravis:
      return "usb+aravis";
    case Backend::kReplay:
      return "replay";
  }
  return "?";
}

// directions.optimize: the directions chosen for the plan's basis, k and eta under the
// gantry's constraints, scored over the sample's field of view at the arms' distances (what
// `acq directions optimize` does); deterministic for a seed, so a resumed run gets the same.
static void OptimizePlanDirections(Plan* plan) {
  const MappedBasis mapped = MappedBasis::Open(plan->basis_file);
  OptimizerOptions o;
  o.n = plan->optimize_n;
  o.k = std::min(plan->components, plan->optimize_n);
  o.seed = plan->optimize_seed;
  o.candidates = plan->optimize_candidates;
  o.constraints = plan->motion.constraints;
  o.eta = plan->eta;
  o.geometry = {plan->camera_distance_mm, plan->light_distance_mm,
                std::max(plan->sample_width_mm, plan->sample_height_mm)};
  o.progress = false;
  o.Check(mapped.View());
  const OptimizedDirections result = OptimizeDirections(mapped.View(), o);
  plan->directions = result.directions;
  for (std::size_t i = 0; i < plan->directions.size(); ++i)
    plan->directions[i].where = "optimised direction " + std::to_string(i + 1);
  char what[160];
  std::snprintf(what, sizeof what, "%d directions optimised (seed %llu, condition number %.4g)",
                o.n, (unsigned long long)o.seed, result.condition);
  plan->directions_file = what;
  CheckReachable(plan->directions, plan->motion);
}

Plan LoadPlan(const std::string& path, const std::string& relative_to) {
  const YAML::Node root = LoadPlanDocument(path);
  Plan plan;
  plan.path = path;
  // Resolve() takes a file whose folder the paths are relative to.
  const std::string base = relative_to.empty() ? path : (fs::path(relative_to) / "plan").string();
  const Section top(root, path, "",
                    {"version", "backend", "output", "replay", "sample", "gantry", "camera",
                     "directions", "calibration", "spectralon", "reconstruction", "sim"});
  if (top.Integer("version", 1) != 1)
    throw UserError(top.Where("version"), "plan version " + top.Text("version") + " is not known",
                    "this acqd reads version 1");
  const std::string backend = top.Required("backend");
  if (backend == "sim")
    plan.backend = Backend::kSim;
  else if (backend == "usb+aravis")
    plan.backend = Backend::kUsbAravis;
  else if (backend == "replay")
    plan.backend = Backend::kReplay;
  else
    throw UserError(top.Where("backend"), "unknown backend '" + backend + "'",
                    "use sim, usb+aravis or replay");
  plan.output = Resolve(base, top.Required("output"));
  if (plan.backend == Backend::kReplay) {
    plan.replay_session = Resolve(base, top.Required("replay"));
    if (!fs::is_directory(plan.replay_session))
      throw UserError(top.Where("replay"), "no session directory " + plan.replay_session,
                      "give the directory of a recorded session");
    std::error_code ec;
    if (fs::exists(plan.output) && fs::equivalent(plan.output, plan.replay_session, ec))
      throw UserError(top.Where("output"),
                      "the replay would write into the session it replays (" + plan.output + ")",
                      "give the replay its own output directory");
  }

  const Section sample = top.Child("sample", {"size_mm"});
  const std::vector<double> size = sample.Numbers("size_mm");
  if (!size.empty()) {
    // Up to a metre: the gantry's arms are about that far away.
    if (size.size() != 2 || !(size[0] > 0) || !(size[1] > 0) || size[0] > 1000 || size[1] > 1000)
      throw UserError(sample.Where("size_mm"),
                      "sample.size_mm must be two numbers from above 0 to 1000",
                      "width and height of the sample in mm, like [70, 70]");
    plan.sample_width_mm = size[0];
    plan.sample_height_mm = size[1];
  }

  const Section gantry =
      top.Child("gantry", {"usb", "limits", "axes", "camera_distance_mm", "light_distance_mm"});
  const Section usb = gantry.Child("usb", {"vid", "pid", "serial"});
  plan.usb.vendor_id = std::uint16_t(usb.Integer("vid", plan.usb.vendor_id, 0, 0xFFFF));
  plan.usb.product_id = std::uint16_t(usb.Integer("pid", plan.usb.product_id, 0, 0xFFFF));
  plan.usb.serial = usb.Text("serial");
  usb.At("vid", [&] { plan.usb.Check(); });
  const Section limits = gantry.Child(
      "limits", {"max_camera_zenith_deg", "max_light_zenith_deg", "min_separation_deg"});
  DirectionConstraints& c = plan.motion.constraints;
  c.max_camera_zenith =
      DegToRad(limits.Number("max_camera_zenith_deg", RadToDeg(c.max_camera_zenith)));
  c.max_light_zenith =
      DegToRad(limits.Number("max_light_zenith_deg", RadToDeg(c.max_light_zenith)));
  c.min_separation = DegToRad(limits.Number("min_separation_deg", RadToDeg(c.min_separation)));
  gantry.At("limits", [&] { c.Check(); });
  const Section axes = gantry.Child("axes", {"theta_speed_deg_s", "theta_accel_deg_s2",
                                             "phi_speed_deg_s", "phi_accel_deg_s2", "settle_s"});
  GantryMotion& m = plan.motion;
  m.ReadAxes([&](const std::string& key, double fallback) { return axes.Number(key, fallback); });
  gantry.At("axes", [&] { m.Check(); });
  for (auto [key, value] : {std::pair{"camera_distance_mm", &plan.camera_distance_mm},
                            std::pair{"light_distance_mm", &plan.light_distance_mm}}) {
    *value = gantry.Number(key, *value);
    if (!(*value >= 50 && *value <= 1e5))
      throw UserError(gantry.Where(key), gantry.Qualified(key) + " must be from 50 to 100000 mm",
                      "the distance from the sample's centre to the arm's camera or light");
  }

  const Section camera = top.Child("camera", {"id", "pixel_format", "gain_db", "hdr"});
  plan.camera_id = camera.Text("id");
  camera.At("pixel_format", [&] {
    plan.camera.pixel_format = ParsePixelFormat(camera.Text("pixel_format", "Mono16"), "");
  });
  plan.camera.gain_db = camera.Number("gain_db", 0);
  const Section hdr = camera.Child("hdr", {"bracket_us", "auto"});
  plan.bracket_us = hdr.Numbers("bracket_us");
  plan.auto_bracket = hdr.Flag("auto", plan.bracket_us.empty());
  if (plan.auto_bracket && !plan.bracket_us.empty())
    throw UserError(hdr.Where("auto"), "camera.hdr has both auto and bracket_us",
                    "choose one: a fixed bracket or the automatic one");
  for (double t : plan.bracket_us)
    if (!(t >= 10 && t <= 1e7))
      throw UserError(
          hdr.Where("bracket_us"),
          "camera.hdr.bracket_us: exposure " + std::to_string(t) + " us is outside 10 us to 10 s",
          "exposures are in microseconds");
  if (plan.backend == Backend::kUsbAravis && plan.camera_id.empty())
    throw UserError(camera.Where("id"), "the usb+aravis backend needs camera.id",
                    "`arv-tool-0.8` lists the cameras and their ids");
  plan.camera.exposure_us = plan.bracket_us.empty() ? 10000 : plan.bracket_us.front();
  camera.At("gain_db", [&] { plan.camera.Check(""); });

  const Section directions = top.Child("directions", {"file", "optimize", "validation"});
  const bool optimize = directions.Has("optimize");
  if (optimize == directions.Has("file"))
    throw UserError(directions.Where(optimize ? "file" : "optimize"),
                    optimize ? "directions.file and directions.optimize exclude each other"
                             : "missing 'directions.file' or 'directions.optimize'",
                    "give a directions TSV, or optimize: {n: 20} to choose them for the basis");
  const Section optimizer = directions.Child("optimize", {"n", "seed", "candidates"});
  if (optimize) {
    // Chosen below, once the basis is known (reconstruction.basis).
    plan.optimize_n = int(optimizer.Integer("n", plan.optimize_n, 1, 200));
    plan.optimize_seed = std::uint64_t(optimizer.Integer("seed", 1, 0, LLONG_MAX));
    plan.optimize_candidates =
        int(optimizer.Integer("candidates", plan.optimize_candidates, 1, 1000000));
  } else {
    plan.directions_file = Resolve(base, directions.Required("file"));
    RequireFile(directions, "file", plan.directions_file,
                "give a directions TSV (acq directions optimize writes one)");
    plan.directions = ReadDirectionsTsv(plan.directions_file);  // errors name file:line
    if (plan.directions.empty())
      throw UserError(directions.Where("file"), "no directions in " + plan.directions_file);
    CheckReachable(plan.directions, plan.motion);  // names the direction's file:line and rule
  }
  if (!directions.Text("validation").empty()) {
    plan.validation_file = Resolve(base, directions.Text("validation"));
    RequireFile(directions, "validation", plan.validation_file,
                "give a directions TSV of light/view pairs to check the result against, or "
                "leave directions.validation out");
    plan.validation = ReadDirectionsTsv(plan.validation_file);
    CheckReachable(plan.validation, plan.motion);
  }

  const Section calibration =
      top.Child("calibration", {"intrinsics_captures", "camera_model", "lensmodel", "board"});
  if (calibration.Has("camera_model")) {
    // The lens calibrated before (intrinsics hold while the lens and focus stay as they were).
    if (calibration.Has("intrinsics_captures"))
      throw UserError(calibration.Where("camera_model"),
                      "calibration.camera_model and calibration.intrinsics_captures exclude each "
                      "other",
                      "give the lens's .cameramodel, or the number of board captures to "
                      "calibrate it in this session");
    plan.intrinsics_file = Resolve(base, calibration.Text("camera_model"));
    RequireFile(calibration, "camera_model", plan.intrinsics_file,
                "give a .cameramodel written by acqd or `acq calibrate intrinsics`");
    plan.intrinsics_captures = 0;
  } else {
    plan.intrinsics_captures =
        int(calibration.Integer("intrinsics_captures", plan.intrinsics_captures, 0, 1000));
    if (plan.intrinsics_captures < 3)
      throw UserError(calibration.Where("intrinsics_captures"),
                      "calibration.intrinsics_captures must be at least 3",
                      "20 to 40 is usual; or give calibration.camera_model");
  }
  plan.lensmodel = calibration.Text("lensmodel", plan.lensmodel);
  plan.lensmodel_where = calibration.Where("lensmodel");
  if (plan.lensmodel.rfind("LENSMODEL_", 0) != 0)
    throw UserError(plan.lensmodel_where,
                    "calibration.lensmodel '" + plan.lensmodel + "' is not an mrcal lens model",
                    "like LENSMODEL_OPENCV4 or LENSMODEL_OPENCV8 (docs/lens-model-choice.md)");
  const Section board = calibration.Child("board", {"size", "spacing_mm"});
  const std::vector<int> board_size = board.Counts("size", 2, 100);
  if (!board_size.empty()) {
    if (board_size.size() != 2)
      throw UserError(board.Where("size"), "calibration.board.size must be two counts >= 2",
                      "inner corners across and down, like [10, 10]");
    plan.board_width_n = board_size[0];
    plan.board_height_n = board_size[1];
  }
  plan.board_spacing_mm = board.Number("spacing_mm", plan.board_spacing_mm);
  if (!(plan.board_spacing_mm > 0 && plan.board_spacing_mm <= 1000))
    throw UserError(board.Where("spacing_mm"),
                    "calibration.board.spacing_mm must be from above 0 to 1000 mm");
  plan.spectralon = top.Flag("spectralon", true);
  if (!plan.spectralon && plan.backend != Backend::kSim)
    throw UserError(top.Where("spectralon"),
                    "a real instrument needs the Spectralon captures: they measure the light "
                    "for the reconstruction",
                    "set spectralon: true");

  const Section sim = top.Child("sim", {"materials", "seed", "light_intensity", "time_scale",
                                        "operator", "image_size", "camera_model"});
  if (plan.backend == Backend::kSim) {
    const YAML::Node materials = root["sim"] ? root["sim"]["materials"] : YAML::Node();
    if (!materials || !materials.IsSequence() || materials.size() == 0)
      throw UserError(sim.Where("materials"), "the sim backend needs sim.materials",
                      "list neural-BRDF fits (.h5) for the simulated card's inks, like "
                      "[../data/nbrdf/merl/white-paint.h5]");
    for (const YAML::Node& m : materials) {
      if (!m.IsScalar())
        throw UserError(sim.Where(m), "sim.materials must list file names, not lists or maps");
      const std::string file = Resolve(base, m.as<std::string>());
      if (!fs::is_regular_file(file))
        throw UserError(sim.Where(m), "sim.materials: no such file " + file,
                        "data/nbrdf/merl has the fits of the 100 MERL materials");
      plan.sim_materials.push_back(file);
    }
  }
  plan.sim_seed = std::uint64_t(sim.Integer("seed", 1, 0, LLONG_MAX));
  plan.sim_light_intensity = sim.Number("light_intensity", plan.sim_light_intensity);
  plan.sim_time_scale = sim.Number("time_scale", plan.sim_time_scale);
  plan.sim_operator = sim.Flag("operator", plan.sim_operator);
  if (!(plan.sim_time_scale > 0 && plan.sim_time_scale <= 1000))
    throw UserError(sim.Where("time_scale"), "sim.time_scale must be from above 0 to 1000",
                    "simulated seconds per wall second: 1 is real time");
  if (!(plan.sim_light_intensity > 0))
    throw UserError(sim.Where("light_intensity"), "sim.light_intensity must be positive");
  const std::vector<int> image_size = sim.Counts("image_size", 16, 16384);
  if (!image_size.empty()) {
    if (image_size.size() != 2)
      throw UserError(sim.Where("image_size"), "sim.image_size must be two counts",
                      "the simulated camera's width and height in pixels, like [2048, 2048]");
    plan.sim_image_width = image_size[0];
    plan.sim_image_height = image_size[1];
  }
  if (sim.Has("camera_model")) {
    if (sim.Has("image_size"))
      throw UserError(sim.Where("camera_model"),
                      "sim.camera_model and sim.image_size exclude "
                      "each other",
                      "a camera model has its own image size");
    plan.sim_camera_model = Resolve(base, sim.Text("camera_model"));
    RequireFile(sim, "camera_model", plan.sim_camera_model,
                "give an mrcal .cameramodel for the simulated camera's lens");
  }

  const Section recon = top.Child("reconstruction", {"basis", "k", "eta", "lookup", "row_tile"});
  plan.basis_file = Resolve(base, recon.Required("basis"));
  RequireFile(recon, "basis", plan.basis_file, "build one with `acq basis build` (README)");
  plan.basis_where = recon.Where("basis");
  plan.components_where = recon.Where("k");
  plan.components = int(recon.Integer("k", plan.components, 1, 64));
  plan.eta = recon.Number("eta", plan.eta);
  plan.row_tile = int(recon.Integer("row_tile", plan.row_tile, 1, 4096));
  const std::string lookup = recon.Text("lookup", "nearest");
  if (const std::optional<RowLookup> parsed = ParseRowLookup(lookup))
    plan.lookup = *parsed;
  else
    throw UserError(recon.Where("lookup"), "reconstruction.lookup '" + lookup + "' is not known",
                    "use nearest or interpolated");
  if (!(plan.eta >= 0)) throw UserError(recon.Where("eta"), "reconstruction.eta must be >= 0");
  if (optimize) optimizer.At("n", [&] { OptimizePlanDirections(&plan); });
  return plan;
}

}  // namespace acq
