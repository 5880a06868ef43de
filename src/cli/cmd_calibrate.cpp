// acq calibrate: corner detection, intrinsics (one lens model or the ladder), extrinsics per
// view, correspondence maps, and synthetic calibration data with a known camera.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "calib/correspondence.h"
#include "calib/detect_corners.h"
#include "calib/extrinsics.h"
#include "calib/intrinsics_report.h"
#include "calib/lensmodel_choice.h"
#include "calib/synthetic_board.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "core/angles.h"
#include "core/error.h"

namespace acq::cli {
namespace {

using namespace acq::calib;

BoardSpec Board(const Args& args) {
  const double spacing = args.GetDouble("spacing-mm", 0);
  return ParseBoardSize(args.Required("board"), args.Has("spacing-mm") ? spacing : 1.0, "--board");
}

std::vector<std::string> Images(const Args& args) {
  std::vector<std::string> out = args.All("images");
  out.insert(out.end(), args.positionals().begin(), args.positionals().end());
  return out;
}

// Observations from --corners-cache (read if it exists, else written after detecting) and/or
// detection in the images given.
std::vector<BoardObservation> Observations(const Args& args, const BoardSpec& board) {
  const std::vector<std::string> images = Images(args);
  const std::string cache = args.Get("corners-cache");
  if (!cache.empty() && std::filesystem::exists(cache)) {
    std::fprintf(stderr, "reading corners from %s\n", cache.c_str());
    return ReadCornersCache(cache, board);
  }
  if (images.empty())
    throw UserError("acq calibrate", "no images given",
                    "name the board images (e.g. --images calib/*.png) or an existing "
                    "--corners-cache");
  const Detector detector = ParseDetector(args.Get("detector", "auto"), board);
  std::fprintf(stderr, "detecting %dx%d corners in %zu images\n", board.width_n, board.height_n,
               images.size());
  std::vector<BoardObservation> obs =
      DetectCornersInFiles(images, board, detector, args.Has("quiet"));
  if (!cache.empty()) {
    WriteCornersCache(cache, obs);
    std::fprintf(stderr, "wrote %s\n", cache.c_str());
  }
  return obs;
}

// The imager size: --imagersize W,H, or read from the first image that exists.
std::pair<int, int> ImagerSize(const Args& args, const std::vector<BoardObservation>& obs) {
  if (args.Has("imagersize")) {
    const std::vector<std::string> wh = args.All("imagersize");
    if (wh.size() != 2) throw UserError("--imagersize", "expected W,H");
    return {std::stoi(wh[0]), std::stoi(wh[1])};
  }
  for (const BoardObservation& o : obs) {
    if (!std::filesystem::exists(o.image)) continue;
    const cv::Mat im = cv::imread(o.image, cv::IMREAD_UNCHANGED);
    if (!im.empty()) return {im.cols, im.rows};
  }
  throw UserError("acq calibrate", "cannot tell the imager size (no image in the cache exists)",
                  "give --imagersize W,H");
}

void WritePosesTsv(const std::string& path, const std::vector<std::string>& names,
                   const std::vector<Pose>& poses, const std::vector<Eigen::Vector3d>& lights,
                   const std::string& what) {
  std::ofstream out(path);
  if (!out) throw UserError(path, "cannot write", "check the folder exists");
  out << "# " << what << ": rt as mrcal (Rodrigues r, then t in mm); light position in the "
      << "sample frame, mm\n# name\tr0\tr1\tr2\tt0\tt1\tt2\tlight_x_mm\tlight_y_mm\tlight_z_mm\n";
  char line[512];
  for (std::size_t i = 0; i < poses.size(); ++i) {
    std::snprintf(line, sizeof line,
                  "%s\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.10g\t%.6g\t%.6g\t%.6g\n",
                  names[i].c_str(), poses[i].r.x(), poses[i].r.y(), poses[i].r.z(), poses[i].t.x(),
                  poses[i].t.y(), poses[i].t.z(), lights[i].x(), lights[i].y(), lights[i].z());
    out << line;
  }
}

struct PoseRow {
  std::string name;
  Pose pose;
  Eigen::Vector3d light;
};

std::vector<PoseRow> ReadPosesTsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UserError(path, "cannot open the views file", "check the path");
  std::vector<PoseRow> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    PoseRow row;
    double v[9];
    s >> row.name;
    for (double& x : v) s >> x;
    if (!s)
      throw UserError(path + ":" + std::to_string(n),
                      "expected name, r0 r1 r2, t0 t1 t2, light_x_mm light_y_mm light_z_mm");
    row.pose = Pose::FromRt(v);
    row.light = {v[6], v[7], v[8]};
    out.push_back(row);
  }
  return out;
}

Eigen::Vector3d LightArg(const Args& args) {
  const std::vector<std::string> v = args.All("light-in-sample-mm");
  if (v.empty()) return {0, 0, 1000};
  if (v.size() != 3) throw UserError("--light-in-sample-mm", "expected X,Y,Z");
  return {std::stod(v[0]), std::stod(v[1]), std::stod(v[2])};
}

}  // namespace

int CalibrateDetect(const Argv& argv) {
  const Args args("acq calibrate detect", argv, {"images", "board", "detector", "corners-cache"},
                  {"quiet"});
  const BoardSpec board = Board(args);
  if (!args.Has("corners-cache"))
    throw UserError("acq calibrate detect", "missing --corners-cache FILE", "where to write");
  std::filesystem::remove(args.Get("corners-cache"));
  const std::vector<BoardObservation> obs = Observations(args, board);
  int found = 0;
  for (const BoardObservation& o : obs) found += o.found();
  std::printf("board found in %d of %zu images\n", found, obs.size());
  return found > 0 ? 0 : 1;
}

int CalibrateIntrinsics(const Argv& argv) {
  const Args args("acq calibrate intrinsics", argv,
                  {"images", "board", "spacing-mm", "lensmodel", "focal-px", "detector",
                   "corners-cache", "imagersize", "max-uncertainty-px", "o"},
                  {"force", "no-warp", "no-outlier-rejection", "quiet"});
  if (!args.Has("spacing-mm"))
    throw UserError("acq calibrate intrinsics", "missing --spacing-mm",
                    "the side of one board square in millimetres");
  const BoardSpec board = Board(args);
  const std::string out_path = args.Required("o");
  const std::vector<BoardObservation> obs = Observations(args, board);
  const auto [width, height] = ImagerSize(args, obs);
  IntrinsicsOptions options;
  options.lensmodel = args.Get("lensmodel", "LENSMODEL_OPENCV8");
  options.focal_px = args.GetDouble("focal-px", 0);
  options.board_warp = !args.Has("no-warp");
  options.outlier_rejection = !args.Has("no-outlier-rejection");
  if (options.lensmodel == "auto") {
    IntrinsicsOptions ladder_options = options;
    ladder_options.lensmodel = "LENSMODEL_OPENCV4";
    ladder_options.Check();
    const double focal =
        options.focal_px > 0 ? options.focal_px : EstimateFocalPx(width, height, board, obs);
    std::printf("lens-model ladder (cross-validated on two halves of the images):\n");
    const LensModelChoice choice =
        ChooseLensModel(width, height, board, obs, ladder_options, DefaultLadder(width, focal));
    PrintLadder(stdout, choice);
    options.lensmodel = choice.rows[choice.chosen].lensmodel;
  }
  const IntrinsicsSolution solution = SolveIntrinsics(width, height, board, obs, options);
  ReportLimits limits;
  limits.max_uncertainty_px = args.GetDouble("max-uncertainty-px", limits.max_uncertainty_px);
  const CalibrationReport report = MakeReport(solution, obs, limits);
  PrintReport(stdout, solution, report);
  if (report.refuse && !args.Has("force")) {
    std::printf("NOT WRITTEN: %s (fix the data set as the warnings say, or --force)\n",
                out_path.c_str());
    return 2;
  }
  solution.problem.camera().Write(out_path);
  std::printf("wrote %s%s\n", out_path.c_str(),
              report.refuse ? " (forced despite the warnings)" : "");
  return 0;
}

int CalibrateExtrinsics(const Argv& argv) {
  const Args args("acq calibrate extrinsics", argv,
                  {"camera", "images", "board", "spacing-mm", "detector", "light-in-sample-mm",
                   "corners-cache", "o"},
                  {"quiet"});
  if (!args.Has("spacing-mm"))
    throw UserError("acq calibrate extrinsics", "missing --spacing-mm", "the square side in mm");
  const CameraModel camera = CameraModel::Read(args.Required("camera"));
  const BoardSpec board = Board(args);
  const std::vector<BoardObservation> obs = Observations(args, board);
  std::vector<std::string> names;
  std::vector<Pose> poses;
  for (const BoardObservation& o : obs) {
    const ExtrinsicsResult r = SolveCamFromSample(camera, board, o);
    const Eigen::Vector3d c = r.cam_from_sample.Inverse().t;
    std::printf(
        "%s: camera at (%.2f, %.2f, %.2f) mm in the sample frame, zenith %.3f deg, "
        "RMS %.4f px over %d corners\n",
        o.image.c_str(), c.x(), c.y(), c.z(), RadToDeg(std::acos(c.z() / c.norm())), r.rms_px,
        r.corners);
    names.push_back(std::filesystem::path(o.image).stem().string());
    poses.push_back(r.cam_from_sample);
  }
  const std::string out = args.Required("o");
  WritePosesTsv(out, names, poses, std::vector<Eigen::Vector3d>(poses.size(), LightArg(args)),
                "cam_from_sample per view");
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

int CalibrateCorrespondence(const Argv& argv) {
  const Args args("acq calibrate correspondence", argv,
                  {"camera", "views", "reference", "region", "o"}, {});
  const CameraModel camera = CameraModel::Read(args.Required("camera"));
  const std::vector<PoseRow> views = ReadPosesTsv(args.Required("views"));
  const std::string reference_name = args.Required("reference");
  ReferenceView ref{camera, {}};
  bool found = false;
  for (const PoseRow& v : views)
    if (v.name == reference_name) {
      ref.cam_from_sample = v.pose;
      found = true;
    }
  if (!found)
    throw UserError(args.Get("views"), "has no view named '" + reference_name + "'",
                    "--reference names the view taken with the camera at theta = 0");
  if (args.Has("region")) {
    const std::vector<std::string> r = args.All("region");
    if (r.size() != 4) throw UserError("--region", "expected X0,Y0,W,H of the reference image");
    ref.x0 = std::stoi(r[0]);
    ref.y0 = std::stoi(r[1]);
    ref.width = std::stoi(r[2]);
    ref.height = std::stoi(r[3]);
  }
  const std::filesystem::path dir = args.Required("o");
  std::filesystem::create_directories(dir);
  const std::vector<Eigen::Vector3d> points = SamplePoints(ref);  // the same for every view
  for (std::size_t i = 0; i < views.size(); ++i) {
    const CalibratedView view{camera, views[i].pose, views[i].light, std::nullopt};
    FloatPlanes map = ComputeCorrespondence(ref, points, view);
    map.attributes["acqView"] = views[i].name;
    map.attributes["acqReferenceView"] = reference_name;
    map.attributes["acqCameraModel"] = args.Get("camera");
    char name[32];
    std::snprintf(name, sizeof name, "%03zu.exr", i);
    WriteFloatPlanesExr((dir / name).string(), map);
    int visible = 0;
    for (float v : map.planes["visible"]) visible += v > 0;
    std::printf("%s: view %s, %d of %d reference pixels visible\n", (dir / name).c_str(),
                views[i].name.c_str(), visible, map.width * map.height);
  }
  return 0;
}

int CalibrateSynthesize(const Argv& argv) {
  const Args args("acq calibrate synthesize", argv,
                  {"camera", "board", "spacing-mm", "n", "noise-px", "seed", "min-distance-mm",
                   "max-distance-mm", "max-tilt-deg", "centre-spread", "o"},
                  {"render", "partial-boards"});
  const CameraModel camera =
      args.Has("camera") ? CameraModel::Read(args.Get("camera")) : ExampleCamera();
  const BoardSpec board =
      ParseBoardSize(args.Get("board", "10x10"), args.GetDouble("spacing-mm", 25), "--board");
  BoardPoseSampling sampling;
  sampling.min_distance_mm = args.GetDouble("min-distance-mm", 300, 1, 1e6);
  sampling.max_distance_mm = args.GetDouble("max-distance-mm", 600, 1, 1e6);
  sampling.max_tilt_deg = args.GetDouble("max-tilt-deg", sampling.max_tilt_deg);
  sampling.centre_spread = args.GetDouble("centre-spread", sampling.centre_spread);
  sampling.whole_board_in_view = !args.Has("partial-boards");
  sampling.seed = static_cast<std::uint64_t>(args.GetInt("seed", 1));
  const int n = args.GetInt("n", 30, 1, 10000);
  const std::vector<Pose> poses = SampleBoardPoses(camera, board, n, sampling);
  if (static_cast<int>(poses.size()) < n)
    throw UserError("acq calibrate synthesize",
                    "could place only " + std::to_string(poses.size()) + " boards in view",
                    "allow --partial-boards, a smaller board or a larger distance range");
  const std::filesystem::path dir = args.Required("o");
  std::filesystem::create_directories(dir);
  std::vector<BoardObservation> obs =
      SynthesizeCorners(camera, board, poses, args.GetDouble("noise-px", 0.3, 0, 100),
                        static_cast<std::uint64_t>(args.GetInt("seed", 1)) + 1000);
  std::vector<std::string> names;
  for (std::size_t f = 0; f < obs.size(); ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "board-%03zu.png", f);
    obs[f].image = name;
    names.push_back(name);
    if (args.Has("render")) {
      BoardRenderOptions render;
      render.seed = f + 1;
      cv::imwrite((dir / name).string(), RenderBoard(camera, board, poses[f], render));
    }
  }
  camera.Write((dir / "truth.cameramodel").string());
  WriteCornersCache((dir / "corners.vnl").string(), obs);
  WritePosesTsv((dir / "poses.tsv").string(), names, poses,
                std::vector<Eigen::Vector3d>(poses.size(), Eigen::Vector3d::Zero()),
                "cam_from_board per image (truth)");
  std::printf("wrote %zu boards to %s (truth.cameramodel, corners.vnl, poses.tsv%s)\n",
              poses.size(), dir.c_str(), args.Has("render") ? ", board-NNN.png" : "");
  return 0;
}

}  // namespace acq::cli
