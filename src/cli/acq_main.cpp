// acq: the offline tool for the stages that run on files.
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <string>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/error.h"

namespace {

struct Command {
  std::function<int(const acq::cli::Argv&)> run;
  const char* usage;
};

const std::map<std::string, Command>& Commands() {
  using namespace acq::cli;
  static const std::map<std::string, Command> commands = {
      {"basis build",
       {BasisBuild,
        "acq basis build MATERIALS... -o|--output BASIS [--components K] [--holdout-every N "
        "--holdout-offset I] [--holdout NAME,...] [--quiet]\n"
        "  MATERIALS: MERL .binary files, neural-BRDF .h5 fits, or folders of them.\n"
        "  Hold out every N-th material by sorted name starting at 0-based I, and/or by name."}},
      {"basis eval",
       {BasisEval,
        "acq basis eval --basis BASIS --directions TSV [MATERIALS...] [--k 20] [--eta 20]\n"
        "               [--write-recon DIR] [--csv FILE] [--all-given]\n"
        "  Reconstructs each material (default: the basis's held-out set, found in MATERIALS or\n"
        "  data/nbrdf/merl) from its values at the directions and prints per-channel errors;\n"
        "  --all-given scores every material given, held out or not."}},
      {"basis info", {BasisInfo, "acq basis info BASIS [--no-verify]"}},
      {"material convert",
       {MaterialConvert,
        "acq material convert MATERIALS... -o DIR\n"
        "  Tabulates neural-BRDF fits (or copies MERL files) as MERL .binary files in DIR."}},
      {"directions random",
       {DirectionsRandom,
        "acq directions random --n N [--seed S] -o TSV\n"
        "  N directions, light and camera uniform over the hemisphere."}},
      {"directions optimize",
       {DirectionsOptimize,
        "acq directions optimize --basis BASIS --n N -o TSV [--k N] [--seed 1] [--candidates "
        "1000]\n"
        "    [--max-camera-zenith-deg 65] [--max-light-zenith-deg 85] [--min-separation-deg 20]\n"
        "    [--unconstrained] [--fov-deg F | --sample-size-mm S] [--camera-distance-mm 1000]\n"
        "    [--light-distance-mm 1000] [--fov-grid 3] [--fov-objective worst|mean]\n"
        "    [--score expected-error|condition] [--eta 20] [--max-condition 200] [--quiet]\n"
        "  Minimises the condition number of the sampled basis rows (NJR15), under the gantry's\n"
        "  constraints; with a field of view, the worst (or mean) over positions on the sample."}},
      {"directions eval",
       {DirectionsEval,
        "acq directions eval --basis BASIS --directions TSV [MATERIALS...] [--k n] [--eta 20]\n"
        "    [--fov-deg 0,4,10 | --sample-size-mm S] [--camera-distance-mm 1000]\n"
        "    [--light-distance-mm 1000] [--grid 10] [--ignore-near-field] [--noise 0,0.05]\n"
        "    [--noise-trials 8] [--seed 1] [--csv FILE --label L] [--all-given]\n"
        "  Condition numbers and held-out log-space error over a field of view, each position\n"
        "  with its own true directions and rows (the near-field effect)."}},
      {"directions plan",
       {DirectionsPlan,
        "acq directions plan --directions TSV [-o PLAN.tsv] [--theta-speed-deg-s 30]\n"
        "    [--theta-accel-deg-s2 60] [--phi-speed-deg-s 30] [--phi-accel-deg-s2 60]\n"
        "    [--settle-s 0.5] [--max-camera-zenith-deg 65] [--max-light-zenith-deg 85]\n"
        "    [--min-separation-deg 20] [--azimuth-steps 72] [--half-vector-azimuths fastest]\n"
        "  Checks every direction against the gantry's reach and arm separation, then finds the\n"
        "  shortest collision-free visiting order (choosing each pose's free azimuth) and its\n"
        "  duration, against the file's order, and with the half vectors spread round the normal\n"
        "  (what a relief's normals need). --half-vector-azimuths spread prints and writes that\n"
        "  order."}},
      {"reconstruct synthetic",
       {ReconstructSynthetic,
        "acq reconstruct synthetic --basis BASIS --directions TSV -o MAP.exr [--size 256x256]\n"
        "    [--materials NAME,...] [--materials-dir data/nbrdf/merl] [--fov-deg 4]\n"
        "    [--camera-distance-mm 1000] [--light-distance-mm 1000] [--k 20] [--eta 20]\n"
        "    [--lookup nearest|interpolated] [--band-rows 64] [--noise 0] [--seed 1]\n"
        "    [--ignore-near-field] [--truth-tables] [--score] [--row-tile 1] [--dump DIR]\n"
        "    [--kernel lanes|lanes-single|one-pixel] [--max-condition C] [--min-observations N]\n"
        "    [--sample-size-mm S] [--quiet]\n"
        "    [--method pooled|independent] [--groups 0] [--max-groups 64] [--sample-pixels 8192]\n"
        "    [--design-sigma-deg 0.15]\n"
        "    [--sample card|blend|marble|text | --sample-labels PNG|EXR | --sample-weights EXR]\n"
        "    [--relief-deg S [--fibre-deg F] | --height-map EXR|PNG] [--spread-half-vectors]\n"
        "    [--normals\n"
        "    [--normals-max-tilt-deg 25] [--normals-prior 0.5] [--normals-k 8]\n"
        "    [--normals-criterion fit|held-out|centre] [--normals-score-min-cos 0]\n"
        "    [--normals-evidence 1] [--normals-estimated-min-cos 0]\n"
        "    [--normals-min-tilt-deg 0.75] [--normals-view-weights on|off]\n"
        "    [--normals-search grid|quadratic] [--normals-levels N] [--normals-coarse-reach 1] "
        "[--normals-single-centre]\n"
        "    [--normals-trimmed-views 1] [--normals-max-uncertainty-deg 0]\n"
        "    [--normals-confirm alone|regrouped|all] [--normals-mixed-same-group on|off]\n"
        "    [--normals-same-centre on|off]]\n"
        "  Reconstructs a synthetic printed card from observations made straight from the\n"
        "  ground truth, per pixel, into an SVBRDF map (docs/svbrdf-map.md); --score compares\n"
        "  every pixel with its true material. --method pooled groups the pixels by material\n"
        "  and solves each with a prior towards its group's centre (docs/reconstruction.md);\n"
        "  --groups forces the number of groups (0: chosen by held-out views);\n"
        "  --design-sigma-deg weights each centre to the pixels whose directions lie nearest the\n"
        "  plan's (0: every pixel alike). --sample picks a built-in sample of the materials\n"
        "  (blend, marble and text use the first two); a label image holds each pixel's index\n"
        "  into --materials, a weight image one channel per material, named as it, summing to\n"
        "  one (docs/reconstruction.md). --relief-deg embosses\n"
        "  what is printed and raises a border (steepest slope S degrees; --fibre-deg adds paper\n"
        "  fibre); --height-map gives heights in pixels (EXR plane 'height'; a PNG's full scale\n"
        "  is 8 pixels); --normals estimates each pixel's normal with its BRDF.\n"
        "  --spread-half-vectors sets each view's free azimuth as gantry.half_vector_azimuths:\n"
        "  spread does (else phi_h = 0 for all)."}},
      {"export pbr",
       {ExportPbr,
        "acq export pbr --map MAP.exr -o DIR [--basis BASIS] [--session SESSION] [--name NAME]\n"
        "    [--model schlick|weighted|coated] [--max-zenith-deg 70] [--roughness-steps 16]\n"
        "    [--max-iterations 100] [--quiet]\n"
        "  Fits Lambert + GGX (Schlick F0 colour; weighted: and F90; coated, the default: and a\n"
        "  clearcoat lobe where a pixel needs one) to every pixel's BRDF in the method's log\n"
        "  space; writes glTF 2.0 (material.gltf), MaterialX (material.mtlx), their textures, the\n"
        "  fit's error map and fit.json. --session: the fitted and the measured map against the\n"
        "  session's validation views, and the fit's error per true material in simulation."}},
      {"export mitsuba",
       {ExportMitsuba,
        "acq export mitsuba --map MAP.exr -o DIR [--basis BASIS] [--light-theta-deg 30\n"
        "    --light-phi-deg 0] [--camera-theta-deg 0 --camera-phi-deg 0]\n"
        "    [--camera-distance-mm 1000] [--light-distance-mm 1000]\n"
        "  A Mitsuba 3 scene of the sample with a BSDF plugin evaluating the data-driven map per\n"
        "  texel; render with .venv/bin/python DIR/render.py (docs/export.md)."}},
      {"render quicklook",
       {RenderQuicklook,
        "acq render quicklook --map MAP.exr -o DIR [--basis BASIS]\n"
        "  PNGs of the BRDF at a diffuse and a specular configuration, and of the per-pixel\n"
        "  diagnostics (valid, observations, condition, residual; a pooled map's group and\n"
        "  departure)."}},
      {"render view",
       {RenderView,
        "acq render view --map MAP.exr -o VIEW.png [--light-theta-deg 30 --light-phi-deg 0]\n"
        "    [--camera-theta-deg 0 --camera-phi-deg 0] [--camera-distance-mm 1000]\n"
        "    [--light-distance-mm 1000] [--fov-deg F | --sample-size-mm S] [--exposure E]\n"
        "    [--basis BASIS]\n"
        "  The sample under any arm pose, in reference-view pixels, with near-field directions."}},
      {"render spheres",
       {RenderSpheres,
        "acq render spheres --map MAP.exr --pixel X,Y [--pixel X,Y ...] -o SPHERES.png\n"
        "    [--size 256] [--light-theta-deg 45 --light-phi-deg 135] [--exposure E] [--basis "
        "BASIS]\n"
        "  Spheres with the BRDF of chosen pixels, lit by a distant point light."}},
      {"render export",
       {RenderExport,
        "acq render export --map MAP.exr --pixel X,Y -o PIXEL.binary [--basis BASIS]\n"
        "  A pixel's BRDF as a MERL .binary (pbrt, Mitsuba)."}},
      {"calibrate detect",
       {CalibrateDetect,
        "acq calibrate detect --images IMAGES... --board WxH --corners-cache OUT.vnl\n"
        "    [--detector auto|mrgingham|opencv] [--quiet]\n"
        "  Chessboard corners (WxH inner corners) in mrcal's corners-cache format."}},
      {"calibrate intrinsics",
       {CalibrateIntrinsics,
        "acq calibrate intrinsics (--images IMAGES... | --corners-cache F) --board WxH\n"
        "    --spacing-mm S -o CAMERA.cameramodel [--lensmodel LENSMODEL_OPENCV8|auto]\n"
        "    [--focal-px F] [--imagersize W,H] [--detector auto|mrgingham|opencv]\n"
        "    [--max-uncertainty-px 1] [--force] [--no-warp] [--no-outlier-rejection] [--quiet]\n"
        "  Solves with mrcal in stages and reports residuals, outliers, worst images and the\n"
        "  projection uncertainty; refuses to write a model whose uncertainty exceeds the limit.\n"
        "  auto: the lens-model ladder, cross-validated (docs/lens-model-choice.md)."}},
      {"calibrate extrinsics",
       {CalibrateExtrinsics,
        "acq calibrate extrinsics --camera CAMERA.cameramodel --board WxH --spacing-mm S\n"
        "    --images IMAGES... -o VIEWS.tsv [--light-in-sample-mm X,Y,Z] [--corners-cache F]\n"
        "    [--detector auto|mrgingham|opencv] [--quiet]\n"
        "  cam_from_sample per image of the board lying in the sample plane (intrinsics locked)."}},
      {"calibrate correspondence",
       {CalibrateCorrespondence,
        "acq calibrate correspondence --camera CAMERA.cameramodel --views VIEWS.tsv\n"
        "    --reference NAME -o DIR [--region X0,Y0,W,H]\n"
        "  Per view NNN.exr: where each reference pixel lands, whether visible, and its light\n"
        "  and view directions (docs/calibration.md)."}},
      {"calibrate synthesize",
       {CalibrateSynthesize,
        "acq calibrate synthesize -o DIR [--camera TRUTH.cameramodel] [--board 10x10]\n"
        "    [--spacing-mm 25] [--n 30] [--noise-px 0.3] [--seed 1] [--min-distance-mm 300]\n"
        "    [--max-distance-mm 600] [--max-tilt-deg 40] [--centre-spread 0.8]\n"
        "    [--partial-boards] [--render]\n"
        "  Boards seen by a known camera: truth.cameramodel, corners.vnl, poses.tsv and, with\n"
        "  --render, the images."}},
      {"session repair",
       {SessionRepair,
        "acq session repair SESSION\n"
        "  Rebuilds a session's catalog from its frames' own metadata (step, pose, exposure,\n"
        "  bracket) after catalog.sqlite was lost or emptied; deletes nothing. acqd refuses to\n"
        "  resume such a session and names this command."}},
      {"session process",
       {SessionProcess,
        "acq session process SESSION [--from hdr|calibration|reconstruction]\n"
        "    [--set reconstruction.k=10 ...] [-o NEW]\n"
        "  Runs a captured session's processing again from a stage (default calibration: the\n"
        "  HDR merges reused) with processing settings changed, into the session or into a\n"
        "  new folder NEW (frames linked, never changed); writes the map and the report\n"
        "  there. Capture settings cannot be changed (docs/session-and-plan.md)."}},
  };
  return commands;
}

void PrintUsage(FILE* to) {
  std::fprintf(to, "usage:\n");
  for (const auto& [name, command] : Commands()) std::fprintf(to, "  %s\n\n", command.usage);
}

}  // namespace

int main(int argc, char** argv) {
  // Line-buffered stdout keeps results and warnings (stderr) in order in a shared log.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    PrintUsage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string name = argc >= 3 ? std::string(argv[1]) + " " + argv[2] : argv[1];
  // `acq GROUP --help` (or `acq GROUP`): the usage of each command of the group.
  if (argc == 2 ||
      (argc >= 3 && (!std::strcmp(argv[2], "--help") || !std::strcmp(argv[2], "-h")))) {
    const std::string group = std::string(argv[1]) + " ";
    bool any = false;
    for (const auto& [n, command] : Commands())
      if (n.rfind(group, 0) == 0) {
        std::printf("usage: %s\n\n", command.usage);
        any = true;
      }
    if (any) return argc == 2 ? 2 : 0;
  }
  const auto it = Commands().find(name);
  if (it == Commands().end()) {
    std::fprintf(stderr, "acq: unknown command '%s'\n", name.c_str());
    PrintUsage(stderr);
    return 2;
  }
  acq::cli::Argv args(argv + 3, argv + argc);
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      std::printf("usage: %s\n", it->second.usage);
      return 0;
    }
  }
  acq::cli::SetCommandUsage(it->second.usage);
  try {
    return it->second.run(args);
  } catch (const acq::UserError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "acq %s: internal error: %s\n", name.c_str(), e.what());
    return 3;
  }
}
