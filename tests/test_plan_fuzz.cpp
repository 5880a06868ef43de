// Issue 22: the plan loader on 1,000 seeded mutations of a good plan (values replaced by
// nonsense, lines deleted, duplicated, re-indented, the file cut short, bytes inserted): every
// one is either refused with a UserError that names the plan at a real place (never 0:0), or
// accepted with every setting finite and in its physical range. No other exception, no hang.
// Then the plan's record in a session: a capture setting changed is refused with the difference
// named, a processing setting changed is allowed and recorded.
#include <algorithm>
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "acq/plan.h"
#include "acq/plan_checks.h"
#include "acq/plan_record.h"
#include "core/error.h"
#include "core/pixel_footprint.h"
#include "io/session_catalog.h"
#include "test_helpers.h"

using namespace acq;
namespace fs = std::filesystem;

namespace {

const std::string kData = ACQ_DATA_DIR;

std::string GoodPlan(const std::string& basis) {
  std::ostringstream p;
  p << "version: 1\nbackend: sim\noutput: session\n"
    << "sample:\n  size_mm: [40, 40]\n"
    << "gantry:\n  usb: {vid: 0x1209, pid: 0xacd0}\n"
    << "  limits: {max_camera_zenith_deg: 66, max_light_zenith_deg: 89, min_separation_deg: 20}\n"
    << "  axes: {theta_speed_deg_s: 30, theta_accel_deg_s2: 60, phi_speed_deg_s: 30,\n"
    << "         phi_accel_deg_s2: 60, settle_s: 0.5}\n"
    << "  camera_distance_mm: 1000\n  light_distance_mm: 1000\n"
    << "camera:\n  pixel_format: Mono16\n  gain_db: 0\n  hdr: {bracket_us: [1000, 8000]}\n"
    << "directions:\n  file: " << kData << "/directions/seed_directions_20.tsv\n"
    << "calibration:\n  intrinsics_captures: 20\n  lensmodel: LENSMODEL_OPENCV4\n"
    << "  board: {size: [10, 10], spacing_mm: 20}\n"
    << "spectralon: true\n"
    << "reconstruction:\n  basis: " << basis << "\n  k: 20\n  eta: 40\n  row_tile: 1\n"
    << "sim:\n  materials: [" << kData << "/nbrdf/merl/white-paint.h5]\n"
    << "  seed: 3\n  light_intensity: 2e5\n  time_scale: 10\n";
  return p.str();
}

// Empty when the accepted plan is sane, else what is not.
std::string Insane(const Plan& p) {
  std::string why;
  auto need = [&](bool ok, const char* what) {
    if (!ok) why += std::string(what) + "; ";
  };
  need(p.sample.width_mm > 0 && p.sample.width_mm <= 1000, "sample width");
  need(p.sample.height_mm > 0 && p.sample.height_mm <= 1000, "sample height");
  need(p.gantry.camera_distance_mm >= 50 && p.gantry.camera_distance_mm <= 1e5, "camera distance");
  need(p.gantry.light_distance_mm >= 50 && p.gantry.light_distance_mm <= 1e5, "light distance");
  for (const AxisLimits* a : {&p.gantry.motion.theta, &p.gantry.motion.phi})
    need(std::isfinite(a->speed) && a->speed > 0 && std::isfinite(a->acceleration) &&
             a->acceleration > 0,
         "axis");
  need(p.gantry.motion.settle_s >= 0 && p.gantry.motion.settle_s <= 60, "settle");
  need(!p.directions.empty(), "directions");
  for (double t : p.camera.bracket_us) need(t >= 10 && t <= 1e7, "bracket");
  need(p.camera.auto_bracket != !p.camera.bracket_us.empty(), "bracket kind");
  need(p.camera.settings.gain_db >= 0 && p.camera.settings.gain_db <= 48, "gain");
  need(p.reconstruction.components >= 1 && p.reconstruction.components <= 64, "k");
  need(std::isfinite(p.reconstruction.eta) && p.reconstruction.eta >= 0, "eta");
  need(p.reconstruction.row_tile >= 1, "row tile");
  need(p.calibration.intrinsics_captures >= 3 || !p.calibration.intrinsics_file.empty(),
       "intrinsics");
  need(p.calibration.board_width_n >= 2 && p.calibration.board_height_n >= 2, "board size");
  need(std::isfinite(p.calibration.board_spacing_mm) && p.calibration.board_spacing_mm > 0,
       "board spacing");
  need(p.sim.time_scale > 0 && p.sim.time_scale <= 1000, "time scale");
  need(std::isfinite(p.sim.light_intensity) && p.sim.light_intensity > 0, "light intensity");
  need(!p.sim.materials.empty(), "materials");
  return why;
}

std::string Mutate(const std::string& text, std::mt19937_64& rng) {
  static const char* tokens[] = {"nan",
                                 ".nan",
                                 ".inf",
                                 "-.inf",
                                 "-1",
                                 "0",
                                 "1e308",
                                 "1e999",
                                 "99999999999999999999",
                                 "\"\"",
                                 "[]",
                                 "{}",
                                 "x",
                                 "true",
                                 "0x10000",
                                 "-0",
                                 "3.5",
                                 "[1, 2, 3]",
                                 "~",
                                 "[nan, 1]",
                                 "!!binary aGk=",
                                 "&a 1",
                                 "*a",
                                 "'",
                                 "\"unterminated"};
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  auto pick = [&](std::size_t n) { return std::size_t(rng() % n); };
  // A plan cut to nothing by an earlier mutation: a stray line is all there is to change. (The
  // mutations depend on the plan's text, which holds the checkout's and the temporary folder's
  // paths, so an empty plan comes up in some checkouts only: rng() % 0 was a SIGFPE there.)
  if (lines.empty()) return std::string(tokens[pick(std::size(tokens))]) + "\n";
  const std::size_t i = pick(lines.size());
  switch (rng() % 7) {
    case 0: {  // a value replaced
      const std::size_t colon = lines[i].find(": ");
      if (colon != std::string::npos)
        lines[i] = lines[i].substr(0, colon + 2) + tokens[pick(std::size(tokens))];
      break;
    }
    case 1:
      lines.erase(lines.begin() + long(i));
      break;
    case 2:
      lines.insert(lines.begin() + long(i), lines[i]);
      break;
    case 3:
      lines.insert(lines.begin() + long(i), "  surprise_key: 1");
      break;
    case 4:
      lines[i] = (rng() % 2 ? "  " : "") + lines[i].substr(lines[i].rfind("  ", 0) == 0 ? 2 : 0);
      break;
    case 5: {  // cut short
      std::string joined;
      for (const std::string& l : lines) joined += l + "\n";
      return joined.substr(0, pick(joined.size()));
    }
    case 6: {  // a number inside a flow list or mapping replaced
      const std::size_t digit = lines[i].find_first_of("0123456789");
      if (digit != std::string::npos) lines[i].replace(digit, 1, tokens[pick(std::size(tokens))]);
      break;
    }
  }
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

}  // namespace

TEST_CASE("plan fuzz: 1,000 mutations refused with a place or accepted sane", "[plan]") {
  const test::TempDir tmp;
  const std::string basis = tmp / "basis.acqb";
  std::ofstream(basis) << "the loader only checks that it exists";
  const std::string good = GoodPlan(basis);
  const std::string path = tmp / "plan.yaml";
  std::ofstream(path) << good;
  REQUIRE(Insane(LoadPlan(path)).empty());

  std::mt19937_64 rng(22);
  int refused = 0, accepted = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int n = 0; n < 1000; ++n) {
    std::string text = good;
    for (int m = 0, count = 1 + int(rng() % 3); m < count; ++m) text = Mutate(text, rng);
    std::ofstream(path, std::ios::trunc) << text;
    INFO("mutation " << n << ":\n" << text);
    try {
      const Plan plan = LoadPlan(path);
      CheckOutputFolder(plan.output, path);
      CHECK(Insane(plan) == "");
      ++accepted;
    } catch (const UserError& e) {
      const std::string what = e.what();
      INFO("refused with: " << what);
      // Named at a place: the plan, or a file it names (a direction's file:line).
      const std::string file = e.where().substr(0, e.where().find(':'));
      CHECK((file == path || fs::is_regular_file(file)));
      CHECK(what.find(":0:0") == std::string::npos);
      ++refused;
    }
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WARN("1000 mutated plans: " << refused << " refused, " << accepted << " accepted, " << s << " s");
  // Seeded: the same mutations every run. Both outcomes must occur, or the mutations test
  // nothing (all refused: a loader that refuses everything would pass).
  CHECK(refused > 100);
  CHECK(accepted > 50);
}

TEST_CASE("plan record: a sample file or height map whose content changed is refused, and kept",
          "[plan]") {
  const test::TempDir tmp;
  const std::string basis = tmp / "basis.acqb";
  std::ofstream(basis) << "a basis";
  // The loader checks only that the files exist (acqd reads them when it builds the instrument);
  // the record hashes their bytes, so any content will do here.
  std::ofstream(tmp / "labels.png") << "labels, first version";
  std::ofstream(tmp / "height.png") << "heights";
  const std::string path = tmp / "plan.yaml";
  std::ofstream(path) << GoodPlan(basis)
                      << "  sample: {labels: labels.png}\n  relief: {height_map: height.png}\n";
  const std::string session = tmp / "session";
  SessionCatalog catalog(session);
  CHECK(RecordOrCheckPlan(LoadPlan(path), session, catalog).first_run);
  // Kept with the session, as the materials are: what the frames were rendered from.
  CHECK(fs::exists(session + "/plan_files/labels.png"));
  CHECK(fs::exists(session + "/plan_files/height.png"));
  CHECK_FALSE(RecordOrCheckPlan(LoadPlan(path), session, catalog).first_run);
  // Same names, other bytes: a resume would mix two samples in one map.
  std::ofstream(tmp / "labels.png", std::ios::trunc) << "labels, second version";
  CHECK_THROWS_WITH(
      RecordOrCheckPlan(LoadPlan(path), session, catalog),
      Catch::Contains("change what is captured") && Catch::Contains("sim.sample.labels: sha256:"));
  std::ofstream(tmp / "labels.png", std::ios::trunc) << "labels, first version";
  std::ofstream(tmp / "height.png", std::ios::trunc) << "other heights";
  CHECK_THROWS_WITH(RecordOrCheckPlan(LoadPlan(path), session, catalog),
                    Catch::Contains("sim.relief.height_map: sha256:"));
}

TEST_CASE("plan record: a capture setting changed is refused, a processing one recorded",
          "[plan]") {
  const test::TempDir tmp;
  const std::string basis = tmp / "basis.acqb";
  std::ofstream(basis) << "a basis";
  const std::string path = tmp / "plan.yaml";
  std::ofstream(path) << GoodPlan(basis);
  const std::string session = tmp / "session";
  SessionCatalog catalog(session);
  CHECK(RecordOrCheckPlan(LoadPlan(path), session, catalog).first_run);
  CHECK(fs::exists(session + "/plan.yaml"));
  CHECK(fs::exists(session + "/plan_files/seed_directions_20.tsv"));
  // The same plan again: nothing to say.
  const PlanCheck same = RecordOrCheckPlan(LoadPlan(path), session, catalog);
  CHECK_FALSE(same.first_run);
  CHECK(same.processing_changes.empty());

  auto edited = [&](const std::string& from, const std::string& to) {
    std::string text = GoodPlan(basis);
    text.replace(text.find(from), from.size(), to);
    const std::string p = tmp / "edited.yaml";
    std::ofstream(p, std::ios::trunc) << text;
    return LoadPlan(p);
  };
  // What changes the frames: refused, each difference named.
  for (const auto& [from, to, key] :
       {std::tuple<std::string, std::string, std::string>{"[1000, 8000]", "[1000, 9000]",
                                                          "camera.hdr: 1000 8000 -> 1000 9000"},
        {"size_mm: [40, 40]", "size_mm: [40, 41]", "sample.size_mm: 40 40 -> 40 41"},
        {"seed: 3", "seed: 4", "sim.seed: 3 -> 4"},
        {"settle_s: 0.5", "settle_s: 0.6", "gantry.axes"},
        // The poses' azimuths: recorded when spread (absent, the fastest, as sessions before it).
        {"  camera_distance_mm", "  half_vector_azimuths: spread\n  camera_distance_mm",
         "gantry.half_vector_azimuths: (none) -> spread"},
        {"spacing_mm: 20", "spacing_mm: 25", "calibration.board"},
        {"seed_directions_20.tsv", "validation_3.tsv", "directions.count: 20 -> 3"}}) {
    INFO(from << " -> " << to);
    CHECK_THROWS_WITH(RecordOrCheckPlan(edited(from, to), session, catalog),
                      Catch::Contains("change what is captured") && Catch::Contains(key));
  }
  // The basis's content matters too, though its name is the same.
  std::ofstream(basis, std::ios::trunc) << "another basis";
  const PlanCheck processing = RecordOrCheckPlan(edited("k: 20", "k: 10"), session, catalog);
  REQUIRE(processing.processing_changes.size() == 2);
  CHECK(processing.processing_changes[0].find("reconstruction.basis") == 0);
  CHECK(processing.processing_changes[1] == "reconstruction.k: 20 -> 10");
  CHECK(catalog.Events().back().second ==
        "plan changed for processing: reconstruction.k: 20 -> 10");
}

TEST_CASE("plan record: the camera's pixel spread is that of the camera that took the frames",
          "[plan]") {
  const test::TempDir tmp;
  const std::string basis = tmp / "basis.acqb";
  std::ofstream(basis) << "a basis";
  const auto plan_with = [&](const std::string& sim_lines, const std::string& name) {
    std::string text = GoodPlan(basis);
    text.replace(text.find("  seed: 3\n"), 10, "  seed: 3\n" + sim_lines);
    const std::string p = tmp / name;
    std::ofstream(p) << text;
    return LoadPlan(p);
  };
  // The simulator's camera reads each pixel's centre unless told to integrate.
  const Plan point = plan_with("", "point.yaml");
  CHECK(CameraPixelSpreadPx(point) == 0);
  const Plan area = plan_with("  pixel_samples: 4\n", "area.yaml");
  CHECK(CameraPixelSpreadPx(area) == Approx(std::sqrt(15.0 / 12) / 4));  // 0.2795
  // Many points approach the whole pixel's box, a real sensor's.
  CHECK(PixelSamplesSpreadPx(100) == Approx(kWholePixelSpreadPx).epsilon(1e-4));
  Plan real = point;
  real.backend = Backend::kUsbAravis;
  CHECK(CameraPixelSpreadPx(real) == kWholePixelSpreadPx);
  // A replay's frames are those of the session it replays: its recorded camera's.
  const std::string session = tmp / "session";
  SessionCatalog catalog(session);
  RecordOrCheckPlan(area, session, catalog);
  Plan replay = point;
  replay.backend = Backend::kReplay;
  replay.replay_session = session;
  CHECK(CameraPixelSpreadPx(replay) == CameraPixelSpreadPx(area));
  // A replay of that replay: followed back to the camera that took the frames.
  const std::string replayed = tmp / "replayed";
  SessionCatalog replayed_catalog(replayed);
  RecordOrCheckPlan(replay, replayed, replayed_catalog);
  Plan second = replay;
  second.replay_session = replayed;
  CHECK(CameraPixelSpreadPx(second) == CameraPixelSpreadPx(area));
  replay.replay_session = tmp / "recorded-before-plans";  // no record: taken as a real camera's
  CHECK(CameraPixelSpreadPx(replay) == kWholePixelSpreadPx);
  // Turning the renders' footprint off is a processing setting, recorded.
  CHECK(point.reconstruction.pixel_footprint);  // on unless turned off
  std::string text = GoodPlan(basis);
  text.replace(text.find("  row_tile: 1\n"), 14, "  row_tile: 1\n  pixel_footprint: false\n");
  std::ofstream(tmp / "footprint-off.yaml") << text;
  const Plan footprint_off = LoadPlan(tmp / "footprint-off.yaml");
  CHECK_FALSE(footprint_off.reconstruction.pixel_footprint);
  const std::vector<PlanSetting> settings = PlanSettings(footprint_off);
  CHECK(std::any_of(settings.begin(), settings.end(), [](const PlanSetting& s) {
    return s.key == "reconstruction.pixel_footprint" && s.value == "false" &&
           s.kind == PlanSetting::Kind::kProcessing;
  }));
}
