#include "acq/plan.h"

#include <Eigen/LU>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>

#include "acq/plan_record.h"
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
  bool HasMap(const std::string& key) const { return Has(key) && node_[key].IsMap(); }
  std::string Where(const YAML::Node& n) const {
    YAML::Mark m = n.Mark();
    if (m.is_null()) m = fallback_;  // a node made here, not read from the file
    if (m.is_null()) m.line = m.column = 0;
    return Place(file_, m);
  }
  // A key of this section, or a dotted path into its children ("board.spacing_mm"); the
  // section's own place where the key is absent.
  std::string Where(const std::string& key) const {
    const std::size_t dot = key.find('.');
    if (dot != std::string::npos && Has(key.substr(0, dot)) &&
        node_[key.substr(0, dot)][key.substr(dot + 1)])
      return Where(node_[key.substr(0, dot)][key.substr(dot + 1)]);
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
  // Runs a section's Check(): its UserError names the key (where()), re-thrown at that key's
  // place as "section.key must ...".
  void Checked(const std::function<void()>& check) const {
    try {
      check();
    } catch (const UserError& e) {
      throw UserError(Where(e.where()), Qualified(e.where()) + " " + e.problem(), e.fix());
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

// directions.optimize: the directions chosen for the plan's basis, k and eta under the
// gantry's constraints, scored over the sample's field of view at the arms' distances (what
// `acq directions optimize` does); deterministic for a seed, so a resumed run gets the same.
void OptimizePlanDirections(Plan* plan) {
  const MappedBasis mapped = MappedBasis::Open(plan->reconstruction.basis_file);
  OptimizerOptions o;
  o.n = plan->optimize_n;
  o.k = std::min(plan->reconstruction.components, plan->optimize_n);
  o.seed = plan->optimize_seed;
  o.candidates = plan->optimize_candidates;
  o.constraints = plan->gantry.motion.constraints;
  o.eta = plan->reconstruction.eta;
  o.geometry = {plan->gantry.camera_distance_mm, plan->gantry.light_distance_mm,
                std::max(plan->sample.width_mm, plan->sample.height_mm)};
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
  CheckReachable(plan->directions, plan->gantry.motion);
}

// version, backend, output, replay.
void ReadTop(const Section& top, const std::string& base, Plan* plan) {
  if (top.Integer("version", 1) != 1)
    throw UserError(top.Where("version"), "plan version " + top.Text("version") + " is not known",
                    "this acqd reads version 1");
  const std::string backend = top.Required("backend");
  if (backend == "sim")
    plan->backend = Backend::kSim;
  else if (backend == "usb+aravis")
    plan->backend = Backend::kUsbAravis;
  else if (backend == "replay")
    plan->backend = Backend::kReplay;
  else
    throw UserError(top.Where("backend"), "unknown backend '" + backend + "'",
                    "use sim, usb+aravis or replay");
  plan->output = Resolve(base, top.Required("output"));
  if (plan->backend != Backend::kReplay) return;
  plan->replay_session = Resolve(base, top.Required("replay"));
  if (!fs::is_directory(plan->replay_session))
    throw UserError(top.Where("replay"), "no session directory " + plan->replay_session,
                    "give the directory of a recorded session");
  std::error_code ec;
  if (fs::exists(plan->output) && fs::equivalent(plan->output, plan->replay_session, ec))
    throw UserError(top.Where("output"),
                    "the replay would write into the session it replays (" + plan->output + ")",
                    "give the replay its own output directory");
}

SampleSpec ReadSample(const Section& top) {
  const Section sample = top.Child("sample", {"size_mm"});
  SampleSpec s;
  const std::vector<double> size = sample.Numbers("size_mm");
  if (!size.empty()) {
    if (size.size() != 2)
      throw UserError(sample.Where("size_mm"), "sample.size_mm must be two numbers",
                      "width and height of the sample in mm, like [70, 70]");
    s.width_mm = size[0];
    s.height_mm = size[1];
  }
  sample.Checked([&] { s.Check(); });
  return s;
}

GantrySpec ReadGantry(const Section& top) {
  const Section gantry = top.Child("gantry", {"usb", "limits", "axes", "camera_distance_mm",
                                              "light_distance_mm", "half_vector_azimuths"});
  GantrySpec g;
  const Section usb = gantry.Child("usb", {"vid", "pid", "serial"});
  g.usb.vendor_id = std::uint16_t(usb.Integer("vid", g.usb.vendor_id, 0, 0xFFFF));
  g.usb.product_id = std::uint16_t(usb.Integer("pid", g.usb.product_id, 0, 0xFFFF));
  g.usb.serial = usb.Text("serial");
  usb.At("vid", [&] { g.usb.Check(); });
  const Section limits = gantry.Child(
      "limits", {"max_camera_zenith_deg", "max_light_zenith_deg", "min_separation_deg"});
  DirectionConstraints& c = g.motion.constraints;
  c.max_camera_zenith =
      DegToRad(limits.Number("max_camera_zenith_deg", RadToDeg(c.max_camera_zenith)));
  c.max_light_zenith =
      DegToRad(limits.Number("max_light_zenith_deg", RadToDeg(c.max_light_zenith)));
  c.min_separation = DegToRad(limits.Number("min_separation_deg", RadToDeg(c.min_separation)));
  gantry.At("limits", [&] { c.Check(); });
  const Section axes = gantry.Child("axes", {"theta_speed_deg_s", "theta_accel_deg_s2",
                                             "phi_speed_deg_s", "phi_accel_deg_s2", "settle_s"});
  g.motion.ReadAxes(
      [&](const std::string& key, double fallback) { return axes.Number(key, fallback); });
  gantry.At("axes", [&] { g.motion.Check(); });
  if (gantry.Has("half_vector_azimuths")) {
    const std::string name = gantry.Text("half_vector_azimuths");
    const std::optional<HalfVectorAzimuths> parsed = HalfVectorAzimuthsNamed(name);
    if (!parsed)
      throw UserError(gantry.Where("half_vector_azimuths"),
                      "gantry.half_vector_azimuths '" + name + "' is not known",
                      "use fastest or spread (spread: what a relief's normals need)");
    g.motion.half_vector_azimuths = *parsed;
  }
  g.camera_distance_mm = gantry.Number("camera_distance_mm", g.camera_distance_mm);
  g.light_distance_mm = gantry.Number("light_distance_mm", g.light_distance_mm);
  gantry.Checked([&] { g.Check(); });
  return g;
}

CameraSpec ReadCamera(const Section& top, Backend backend) {
  const Section camera = top.Child(
      "camera", {"id", "pixel_format", "gain_db", "hdr", "colour_matrix", "colour_chart"});
  CameraSpec c;
  c.id = camera.Text("id");
  camera.At("pixel_format", [&] {
    c.settings.pixel_format = ParsePixelFormat(camera.Text("pixel_format", "Mono16"), "");
  });
  c.settings.gain_db = camera.Number("gain_db", 0);
  if (camera.Has("colour_matrix")) {
    const std::vector<double> m = camera.Numbers("colour_matrix");
    if (m.size() != 9)
      throw UserError(camera.Where("colour_matrix"),
                      "camera.colour_matrix must hold 9 numbers, not " + std::to_string(m.size()),
                      "the 3 x 3 matrix from camera RGB to linear Rec. 709, row by row");
    c.rec709_from_camera = Eigen::Matrix3d();
    for (int i = 0; i < 9; ++i) (*c.rec709_from_camera)(i / 3, i % 3) = m[std::size_t(i)];
  }
  const Section hdr = camera.Child("hdr", {"bracket_us", "auto"});
  c.bracket_us = hdr.Numbers("bracket_us");
  if (hdr.Has("bracket_us") && c.bracket_us.empty())
    throw UserError(hdr.Where("bracket_us"), "camera.hdr.bracket_us is empty",
                    "give the exposures in microseconds, like [1000, 8000, 64000], or auto: true "
                    "for a bracket chosen from the scene");
  c.auto_bracket = hdr.Flag("auto", c.bracket_us.empty());
  if (c.auto_bracket && !c.bracket_us.empty())
    throw UserError(hdr.Where("auto"), "camera.hdr has both auto and bracket_us",
                    "choose one: a fixed bracket or the automatic one");
  camera.Checked([&] { c.Check(); });
  if (camera.Has("colour_chart") && camera.Text("colour_chart") == "not_fitted")
    c.colour_chart = CameraSpec::Chart::kNotFitted;
  else
    c.colour_chart =
        camera.Flag("colour_chart", false) ? CameraSpec::Chart::kFitted : CameraSpec::Chart::kNone;
  camera.At(camera.Has("colour_chart") ? "colour_chart" : "colour_matrix",
            [&] { c.CheckColour(); });
  if (backend == Backend::kUsbAravis && c.id.empty())
    throw UserError(camera.Where("id"), "the usb+aravis backend needs camera.id",
                    "`arv-tool-0.8` lists the cameras and their ids");
  c.settings.exposure_us = c.bracket_us.empty() ? 10000 : c.bracket_us.front();
  camera.At("gain_db", [&] { c.settings.Check(""); });
  return c;
}

// directions: the sample's (a file, or the optimiser's settings: chosen once the basis is known)
// and the validation's. Returns the optimiser's section when they are to be optimised (a
// Section is returned, never assigned: assigning a YAML::Node overwrites the node it refers to).
std::optional<Section> ReadDirections(const Section& top, const std::string& base, Plan* plan) {
  const Section directions = top.Child("directions", {"file", "optimize", "validation"});
  const bool optimize = directions.Has("optimize");
  if (optimize == directions.Has("file"))
    throw UserError(directions.Where(optimize ? "file" : "optimize"),
                    optimize ? "directions.file and directions.optimize exclude each other"
                             : "missing 'directions.file' or 'directions.optimize'",
                    "give a directions TSV, or optimize: {n: 20} to choose them for the basis");
  const Section optimizer = directions.Child("optimize", {"n", "seed", "candidates"});
  const GantryMotion& motion = plan->gantry.motion;
  if (optimize) {
    plan->optimize_n = int(optimizer.Integer("n", plan->optimize_n, 1, 200));
    plan->optimize_seed = std::uint64_t(optimizer.Integer("seed", 1, 0, LLONG_MAX));
    plan->optimize_candidates =
        int(optimizer.Integer("candidates", plan->optimize_candidates, 1, 1000000));
  } else {
    plan->directions_file = Resolve(base, directions.Required("file"));
    RequireFile(directions, "file", plan->directions_file,
                "give a directions TSV (acq directions optimize writes one)");
    plan->directions = ReadDirectionsTsv(plan->directions_file);  // errors name file:line
    if (plan->directions.empty())
      throw UserError(directions.Where("file"), "no directions in " + plan->directions_file);
    CheckReachable(plan->directions, motion);  // names the direction's file:line and rule
  }
  if (!directions.Text("validation").empty()) {
    plan->validation_file = Resolve(base, directions.Text("validation"));
    RequireFile(directions, "validation", plan->validation_file,
                "give a directions TSV of light/view pairs to check the result against, or "
                "leave directions.validation out");
    plan->validation = ReadDirectionsTsv(plan->validation_file);
    CheckReachable(plan->validation, motion);
  }
  if (!optimize) return std::nullopt;
  return optimizer;
}

CalibrationSpec ReadCalibration(const Section& top, const std::string& base) {
  const Section calibration =
      top.Child("calibration", {"intrinsics_captures", "camera_model", "lensmodel", "board"});
  CalibrationSpec c;
  if (calibration.Has("camera_model")) {
    // The lens calibrated before (intrinsics hold while the lens and focus stay as they were).
    if (calibration.Has("intrinsics_captures"))
      throw UserError(calibration.Where("camera_model"),
                      "calibration.camera_model and calibration.intrinsics_captures exclude each "
                      "other",
                      "give the lens's .cameramodel, or the number of board captures to "
                      "calibrate it in this session");
    c.intrinsics_file = Resolve(base, calibration.Text("camera_model"));
    RequireFile(calibration, "camera_model", c.intrinsics_file,
                "give a .cameramodel written by acqd or `acq calibrate intrinsics`");
    c.intrinsics_captures = 0;
  } else {
    c.intrinsics_captures =
        int(calibration.Integer("intrinsics_captures", c.intrinsics_captures, 0, 1000));
  }
  c.lensmodel = calibration.Text("lensmodel", c.lensmodel);
  c.lensmodel_where = calibration.Where("lensmodel");
  const Section board = calibration.Child("board", {"size", "spacing_mm"});
  const std::vector<int> board_size = board.Counts("size", 2, 100);
  if (!board_size.empty()) {
    if (board_size.size() != 2)
      throw UserError(board.Where("size"), "calibration.board.size must be two counts >= 2",
                      "inner corners across and down, like [10, 10]");
    c.board_width_n = board_size[0];
    c.board_height_n = board_size[1];
  }
  c.board_spacing_mm = board.Number("spacing_mm", c.board_spacing_mm);
  calibration.Checked([&] { c.Check(); });
  return c;
}

// The card's inks: every entry a file name of a neural-BRDF fit.
std::vector<std::string> ReadSimMaterials(const YAML::Node& root, const Section& sim,
                                          const std::string& base) {
  const YAML::Node materials = root["sim"] ? root["sim"]["materials"] : YAML::Node();
  if (!materials || !materials.IsSequence() || materials.size() == 0)
    throw UserError(sim.Where("materials"), "the sim backend needs sim.materials",
                    "list neural-BRDF fits (.h5) for the simulated card's inks, like "
                    "[../data/nbrdf/merl/white-paint.h5]");
  std::vector<std::string> files;
  for (const YAML::Node& m : materials) {
    if (!m.IsScalar())
      throw UserError(sim.Where(m), "sim.materials must list file names, not lists or maps");
    const std::string file = Resolve(base, m.as<std::string>());
    if (!fs::is_regular_file(file))
      throw UserError(sim.Where(m), "sim.materials: no such file " + file,
                      "data/nbrdf/merl has the fits of the 100 MERL materials");
    files.push_back(file);
  }
  return files;
}

// sim.sample: {labels: FILE} or {weights: FILE} (docs/session-and-plan.md); the file's contents
// are checked against the materials when the simulated instrument is built (acqd does so
// before its dry run answers).
SampleFile ReadSimSampleFile(const Section& sim, const std::string& base) {
  const Section sample = sim.Child("sample", {"labels", "weights"});
  if (sample.Has("labels") == sample.Has("weights"))
    throw UserError(sim.Where("sample"), "sim.sample needs one of labels and weights",
                    "{labels: FILE} (each pixel a material's index in sim.materials) or "
                    "{weights: FILE.exr} (one plane per material)");
  const bool labels = sample.Has("labels");
  const std::string key = labels ? "labels" : "weights";
  SampleFile f;
  f.kind = labels ? SampleFile::Kind::kLabels : SampleFile::Kind::kWeights;
  f.path = Resolve(base, sample.Text(key));
  RequireFile(sample, key, f.path,
              labels ? "a grey PNG or an EXR with a 'label' plane"
                     : "an EXR with one plane per material, named as the material");
  return f;
}

// sim.relief: the built-in embossing {slope_deg, fibre_deg} or a file {height_map}.
SimSpec::Relief ReadRelief(const Section& relief, const std::string& base) {
  SimSpec::Relief r;
  if (relief.Has("height_map")) {
    if (relief.Has("slope_deg") || relief.Has("fibre_deg"))
      throw UserError(relief.Where("height_map"),
                      "sim.relief.height_map excludes slope_deg and fibre_deg",
                      "the file gives the relief; leave out the built-in relief's keys");
    r.height_map = Resolve(base, relief.Text("height_map"));
    RequireFile(relief, "height_map", r.height_map,
                "an EXR with a 'height' plane or a grey PNG, the sample layout's size");
    return r;
  }
  r.slope_deg = relief.Number("slope_deg", r.slope_deg);
  r.fibre_deg = relief.Number("fibre_deg", r.fibre_deg);
  if (!(r.slope_deg > 0 && r.slope_deg < 60))
    throw UserError(relief.Where("slope_deg"), "sim.relief.slope_deg must be from above 0 to 60",
                    "the steepest slope of the embossed edges, in degrees, like 10");
  if (!(r.fibre_deg >= 0 && r.fibre_deg < 30))
    throw UserError(relief.Where("fibre_deg"), "sim.relief.fibre_deg must be from 0 to 30",
                    "the paper fibre's RMS slope in degrees; 0: none");
  return r;
}

// sim.chart: how the simulated operator lays the colour chart.
SimSpec::Chart ReadSimChart(const Section& chart) {
  SimSpec::Chart c;
  c.laid = chart.Flag("laid", true);
  if (chart.Has("covered_mm")) {
    if (!c.laid)
      throw UserError(chart.Where("covered_mm"),
                      "sim.chart.covered_mm covers a chart that sim.chart.laid leaves out",
                      "give one of them");
    const std::vector<double> box = chart.Numbers("covered_mm");
    if (box.size() != 4 || !(box[0] < box[2] && box[1] < box[3]))
      throw UserError(chart.Where("covered_mm"),
                      "sim.chart.covered_mm must be [x0, y0, x1, y1] with x0 < x1 and y0 < y1",
                      "the rectangle of the sample plane (mm, the chart centred at 0, 0) that a "
                      "grey card covers, like [-20, -14, -6, 0]");
    c.covered_mm = std::array<double, 4>{box[0], box[1], box[2], box[3]};
  }
  if (chart.Has("turned_deg")) {
    const std::optional<ChartTurn> turn =
        ChartTurnFromDegrees(int(chart.Integer("turned_deg", 0, 0, 270)));
    if (!turn)
      throw UserError(chart.Where("turned_deg"), "sim.chart.turned_deg must be 0, 90, 180 or 270",
                      "how far the chart is laid turned, counter-clockwise, from its layout");
    c.turned = *turn;
  }
  return c;
}

SimSpec ReadSim(const YAML::Node& root, const Section& top, const std::string& base,
                Backend backend, bool colour_chart) {
  const Section sim = top.Child("sim", {"materials", "seed", "light_intensity", "time_scale",
                                        "operator", "image_size", "camera_model", "camera_filter",
                                        "light_rgb", "sample", "relief", "chart", "pixel_samples"});
  SimSpec s;
  if (backend == Backend::kSim) s.materials = ReadSimMaterials(root, sim, base);
  if (sim.HasMap("sample")) {
    s.sample_file = ReadSimSampleFile(sim, base);
  } else if (sim.Has("sample")) {
    const std::optional<SampleKind> kind = ParseSampleKind(sim.Text("sample"));
    if (!kind)
      throw UserError(sim.Where("sample"), "sim.sample '" + sim.Text("sample") + "' is not known",
                      "card, blend, marble or text; or {labels: FILE} or {weights: FILE}");
    s.sample = *kind;
    if (s.sample != SampleKind::kCard && backend == Backend::kSim && s.materials.size() < 2)
      throw UserError(sim.Where("sample"),
                      std::string("sim.sample ") + SampleKindName(s.sample) +
                          " mixes two materials; sim.materials lists " +
                          std::to_string(s.materials.size()),
                      "list two materials");
  }
  s.seed = std::uint64_t(sim.Integer("seed", 1, 0, LLONG_MAX));
  s.light_intensity = sim.Number("light_intensity", s.light_intensity);
  s.time_scale = sim.Number("time_scale", s.time_scale);
  s.operator_prompts = sim.Flag("operator", s.operator_prompts);
  // Its upper limit is the simulated instrument's own (sim::InstrumentOptions::Check).
  s.pixel_samples = int(sim.Integer("pixel_samples", s.pixel_samples, 1));
  const std::vector<int> image_size = sim.Counts("image_size", 16, 16384);
  if (!image_size.empty()) {
    if (image_size.size() != 2)
      throw UserError(sim.Where("image_size"), "sim.image_size must be two counts",
                      "the simulated camera's width and height in pixels, like [2048, 2048]");
    s.image_width = image_size[0];
    s.image_height = image_size[1];
  }
  if (sim.Has("camera_model")) {
    if (sim.Has("image_size"))
      throw UserError(sim.Where("camera_model"),
                      "sim.camera_model and sim.image_size exclude each other",
                      "a camera model has its own image size");
    s.camera_model = Resolve(base, sim.Text("camera_model"));
    RequireFile(sim, "camera_model", s.camera_model,
                "give an mrcal .cameramodel for the simulated camera's lens");
  }
  if (sim.Has("camera_filter")) {
    s.camera_filter = ParseCfa(sim.Text("camera_filter"));
    if (!s.camera_filter)
      throw UserError(sim.Where("camera_filter"),
                      "sim.camera_filter '" + sim.Text("camera_filter") + "' is not a filter",
                      "RGGB, GRBG, GBRG, BGGR or none");
  }
  if (sim.Has("light_rgb")) {
    const std::vector<double> rgb = sim.Numbers("light_rgb");
    if (rgb.size() != 3 || !(rgb[0] > 0 && rgb[1] > 0 && rgb[2] > 0))
      throw UserError(sim.Where("light_rgb"), "sim.light_rgb must be three positive numbers",
                      "each Rec. 709 channel's share of the light, like [1, 0.72, 0.42]");
    s.light_rgb = Eigen::Vector3d(rgb[0], rgb[1], rgb[2]);
  }
  if (sim.Has("relief"))
    s.relief = ReadRelief(sim.Child("relief", {"slope_deg", "fibre_deg", "height_map"}), base);
  if (sim.Has("chart")) {
    if (!colour_chart)
      throw UserError(sim.Where("chart"),
                      "sim.chart describes the colour chart, which this plan does not capture",
                      "set camera.colour_chart: true, or leave sim.chart out");
    s.chart = ReadSimChart(sim.Child("chart", {"covered_mm", "laid", "turned_deg"}));
  }
  sim.Checked([&] { s.Check(); });
  return s;
}

ReconstructionSpec ReadReconstruction(const Section& top, const std::string& base) {
  const Section recon = top.Child("reconstruction", {"basis",
                                                     "k",
                                                     "eta",
                                                     "lookup",
                                                     "row_tile",
                                                     "method",
                                                     "groups",
                                                     "design_sigma_deg",
                                                     "normals",
                                                     "normals_prior",
                                                     "normals_mixed_pixels",
                                                     "normals_trimmed_views",
                                                     "normals_max_uncertainty_deg",
                                                     "normals_evidence",
                                                     "normals_score_min_cos",
                                                     "normals_view_weights",
                                                     "normals_min_tilt_deg",
                                                     "normals_confirm",
                                                     "normals_mixed_same_group",
                                                     "normals_same_centre",
                                                     "pixel_footprint"});
  ReconstructionSpec r;
  r.basis_file = Resolve(base, recon.Required("basis"));
  RequireFile(recon, "basis", r.basis_file, "build one with `acq basis build` (README)");
  r.basis_where = recon.Where("basis");
  r.components_where = recon.Where("k");
  r.components = int(recon.Integer("k", r.components, 1, 64));
  r.eta = recon.Number("eta", r.eta);
  r.row_tile = int(recon.Integer("row_tile", r.row_tile, 1, 4096));
  const std::string lookup = recon.Text("lookup", "nearest");
  if (const std::optional<RowLookup> parsed = ParseRowLookup(lookup))
    r.lookup = *parsed;
  else
    throw UserError(recon.Where("lookup"), "reconstruction.lookup '" + lookup + "' is not known",
                    "use nearest or interpolated");
  const std::string method = recon.Text("method", ReconstructionMethodName(r.method));
  if (const std::optional<ReconstructionMethod> parsed = ParseReconstructionMethod(method))
    r.method = *parsed;
  else
    throw UserError(recon.Where("method"), "reconstruction.method '" + method + "' is not known",
                    "use independent or pooled");
  r.groups = int(recon.Integer("groups", r.groups, 0, 1024));
  r.design_sigma_deg = recon.Number("design_sigma_deg", r.design_sigma_deg);
  r.normals = recon.Flag("normals", r.normals);
  r.normals_prior = recon.Number("normals_prior", r.normals_prior);
  r.normals_mixed_pixels = recon.Flag("normals_mixed_pixels", r.normals_mixed_pixels);
  r.normals_trimmed_views = int(
      recon.Integer("normals_trimmed_views", r.normals_trimmed_views, 0, kMaxNormalsTrimmedViews));
  r.normals_max_uncertainty_deg =
      recon.Number("normals_max_uncertainty_deg", r.normals_max_uncertainty_deg);
  r.normals_evidence = recon.Number("normals_evidence", r.normals_evidence);
  r.normals_score_min_cos = recon.Number("normals_score_min_cos", r.normals_score_min_cos);
  r.normals_view_weights = recon.Flag("normals_view_weights", r.normals_view_weights);
  r.normals_min_tilt_deg = recon.Number("normals_min_tilt_deg", r.normals_min_tilt_deg);
  r.normals_mixed_same_group = recon.Flag("normals_mixed_same_group", r.normals_mixed_same_group);
  r.normals_same_centre = recon.Flag("normals_same_centre", r.normals_same_centre);
  r.pixel_footprint = recon.Flag("pixel_footprint", r.pixel_footprint);
  const std::string confirm =
      recon.Text("normals_confirm", NormalConfirmationName(r.normals_confirmation));
  if (const std::optional<NormalConfirmation> parsed = ParseNormalConfirmation(confirm))
    r.normals_confirmation = *parsed;
  else
    throw UserError(recon.Where("normals_confirm"),
                    "reconstruction.normals_confirm '" + confirm + "' is not known",
                    "use alone, regrouped or all (docs/session-and-plan.md)");
  recon.Checked([&] { r.Check(); });
  return r;
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

void SampleSpec::Check() const {
  // Up to a metre: the gantry's arms are about that far away.
  if (!(width_mm > 0 && height_mm > 0 && width_mm <= 1000 && height_mm <= 1000))
    throw UserError("size_mm", "must be two numbers from above 0 to 1000",
                    "width and height of the sample in mm, like [70, 70]");
}

void GantrySpec::Check() const {
  for (auto [key, value] : {std::pair{"camera_distance_mm", camera_distance_mm},
                            std::pair{"light_distance_mm", light_distance_mm}})
    if (!(value >= 50 && value <= 1e5))
      throw UserError(key, "must be from 50 to 100000 mm",
                      "the distance from the sample's centre to the arm's camera or light");
}

void CameraSpec::CheckColour() const {
  const bool colour = CfaOf(settings.pixel_format) != Cfa::kNone;
  const bool fitted = colour_chart == Chart::kFitted;
  if (colour_chart == Chart::kNotFitted && !rec709_from_camera)
    throw UserError("colour_chart", "camera.colour_chart: not_fitted needs camera.colour_matrix",
                    "give the 3 x 3 matrix of a camera characterised before, or set "
                    "colour_chart: true to fit it from the chart");
  if (colour && !rec709_from_camera && !fitted)
    throw UserError("colour_matrix",
                    std::string("a colour camera (") + PixelFormatName(settings.pixel_format) +
                        ") needs camera.colour_chart or camera.colour_matrix",
                    "colour_chart: true captures a ColorChecker to fit its colour matrix; or give "
                    "the 3 x 3 matrix of a camera characterised before (docs/colour.md)");
  if (fitted && rec709_from_camera)
    throw UserError("colour_chart",
                    "camera.colour_chart and camera.colour_matrix exclude each other",
                    "fit the matrix from a chart captured in this session, or give one; not both "
                    "(colour_chart: not_fitted captures the chart and uses the matrix)");
  if (!colour && (rec709_from_camera || ChartCaptured()))
    throw UserError(ChartCaptured() ? "colour_chart" : "colour_matrix",
                    std::string("a mono camera (") + PixelFormatName(settings.pixel_format) +
                        ") has no colour to correct",
                    "leave camera.colour_matrix and camera.colour_chart out, or name a Bayer "
                    "pixel format");
  if (!rec709_from_camera) return;
  const Eigen::Matrix3d& m = *rec709_from_camera;
  if (!m.allFinite()) throw UserError("colour_matrix", "holds a number that is not finite");
  // Relative to its size: a matrix whose rows are nearly dependent mixes the channels into noise.
  const double det = m.determinant(), scale = m.cwiseAbs().maxCoeff();
  if (!(std::abs(det) > 1e-6 * scale * scale * scale))
    throw UserError("colour_matrix", "is not invertible (determinant " + std::to_string(det) + ")",
                    "give the camera's characterised matrix; identity is 1 0 0 0 1 0 0 0 1");
}

void CameraSpec::Check() const {
  for (double t : bracket_us)
    if (!(t >= 10 && t <= 1e7))
      throw UserError("hdr.bracket_us",
                      "must hold exposures from 10 us to 10 s, not " + std::to_string(t) + " us",
                      "exposures are in microseconds");
}

void CalibrationSpec::Check() const {
  if (intrinsics_file.empty() && intrinsics_captures < 3)
    throw UserError("intrinsics_captures", "must be at least 3",
                    "20 to 40 is usual; or give calibration.camera_model");
  if (lensmodel.rfind("LENSMODEL_", 0) != 0)
    throw UserError("lensmodel", "'" + lensmodel + "' is not an mrcal lens model",
                    "like LENSMODEL_OPENCV4 or LENSMODEL_OPENCV8 (docs/lens-model-choice.md)");
  if (!(board_spacing_mm > 0 && board_spacing_mm <= 1000))
    throw UserError("board.spacing_mm", "must be from above 0 to 1000 mm");
}

void SimSpec::Check() const {
  if (!(time_scale > 0 && time_scale <= 1000))
    throw UserError("time_scale", "must be from above 0 to 1000",
                    "simulated seconds per wall second: 1 is real time");
  if (!(light_intensity > 0)) throw UserError("light_intensity", "must be positive");
}

void ReconstructionSpec::Check() const {
  if (!(eta >= 0)) throw UserError("eta", "must be >= 0");
  CheckDesignSigma(design_sigma_deg, "design_sigma_deg");
  if (!(normals_prior >= 0))
    throw UserError("normals_prior", "must be >= 0",
                    "it weighs how near the sample's normal a pixel's normal stays; 0 for none");
  if (!(normals_max_uncertainty_deg >= 0))
    throw UserError("normals_max_uncertainty_deg", "must be >= 0 degrees",
                    "0 (the default) keeps every estimated normal, however uncertain");
  if (!(normals_evidence >= 0))
    throw UserError("normals_evidence", "must be >= 0",
                    "the multiple of the information criterion a tilt must beat; 0 for none");
  if (!(normals_min_tilt_deg >= 0 && normals_min_tilt_deg < 20))
    throw UserError("normals_min_tilt_deg", "must be from 0 to under 20 degrees",
                    "a normal tilted less than this from the sample's is not kept; 0 keeps all");
  if (!(normals_score_min_cos >= 0 && normals_score_min_cos <= 0.9))
    throw UserError("normals_score_min_cos", "must be from 0 to 0.9",
                    "the cosine to a candidate facet at or below which a view or light is left "
                    "out of its score; 0 keeps all but those behind it");
}

namespace {

// A replay serves the recorded frames in the order they were taken, and checks each against the
// settings asked for: a plan that asks for other frames (another HDR bracket, other directions)
// would fail at the first frame that differs, after calibrating on the frames before it. Checked
// at load instead, with every difference listed.
void CheckReplayMatches(const Plan& plan, const Section& top) {
  const std::vector<std::string> differences = ReplayDifferences(plan, plan.replay_session);
  if (differences.empty()) return;
  throw UserError(
      top.Where("replay"),
      "this plan asks for other frames than " + plan.replay_session + " was captured with, in " +
          ListedChanges(differences),
      "replay with the recorded session's plan settings (" + plan.replay_session + "/plan.yaml)");
}

}  // namespace

Plan LoadPlan(const std::string& path, const std::string& relative_to) {
  const YAML::Node root = LoadPlanDocument(path);
  Plan plan;
  plan.path = path;
  // Resolve() takes a file whose folder the paths are relative to.
  const std::string base = relative_to.empty() ? path : (fs::path(relative_to) / "plan").string();
  const Section top(root, path, "",
                    {"version", "backend", "output", "replay", "sample", "gantry", "camera",
                     "directions", "calibration", "spectralon", "reconstruction", "sim"});
  ReadTop(top, base, &plan);
  plan.sample = ReadSample(top);
  plan.gantry = ReadGantry(top);
  plan.camera = ReadCamera(top, plan.backend);
  const std::optional<Section> optimizer = ReadDirections(top, base, &plan);
  plan.calibration = ReadCalibration(top, base);
  plan.spectralon = top.Flag("spectralon", true);
  if (!plan.spectralon && plan.backend != Backend::kSim)
    throw UserError(top.Where("spectralon"),
                    "a real instrument needs the Spectralon captures: they measure the light "
                    "for the reconstruction",
                    "set spectralon: true");
  if (plan.camera.colour_chart == CameraSpec::Chart::kFitted && !plan.spectralon)
    throw UserError(
        top.Where("spectralon"),
        "the colour chart needs the Spectralon captures (its white at the chart's pose)",
        "set spectralon: true, or give camera.colour_matrix instead of the chart");
  plan.sim = ReadSim(root, top, base, plan.backend, plan.camera.ChartCaptured());
  plan.reconstruction = ReadReconstruction(top, base);
  if (optimizer) optimizer->At("n", [&] { OptimizePlanDirections(&plan); });
  if (plan.backend == Backend::kReplay) CheckReplayMatches(plan, top);
  return plan;
}

}  // namespace acq
