// calib/: simulation first, as mrcal tests itself: synthesise boards seen by a known camera, add
// seeded noise, solve, and compare with the truth against the solve's own predicted uncertainty.
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "calib/correspondence.h"
#include "calib/detect_corners.h"
#include "calib/extrinsics.h"
#include "calib/intrinsics_report.h"
#include "calib/lensmodel_choice.h"
#include "calib/synthetic_board.h"
#include "calib/uncertainty.h"
#include "core/angles.h"
#include "core/error.h"
#include "test_helpers.h"

using namespace acq;
using namespace acq::calib;

namespace {

const BoardSpec kBoard{10, 10, 25};

// Boards reaching into the corners of the view (partly outside it), as a careful user takes them.
std::vector<Pose> GoodPoses(const CameraModel& camera, int n, std::uint64_t seed) {
  BoardPoseSampling s;
  s.min_distance_mm = 300;
  s.max_distance_mm = 600;
  s.whole_board_in_view = false;
  s.centre_spread = 1.1;
  s.seed = seed;
  return SampleBoardPoses(camera, kBoard, n, s);
}

double Mahalanobis2(const Eigen::Vector2d& e, const Eigen::Matrix2d& cov) {
  return e.dot(cov.inverse() * e);
}

}  // namespace

TEST_CASE("camera models round-trip through mrcal's file format", "[calib]") {
  test::TempDir dir;
  CameraModel camera = ExampleCamera();
  camera.cam_from_ref.r = {0.01, -0.02, 0.03};
  camera.cam_from_ref.t = {1, 2, 3};
  camera.Write(dir / "c.cameramodel");
  const CameraModel back = CameraModel::Read(dir / "c.cameramodel");
  CHECK(back.lensmodel_name() == "LENSMODEL_OPENCV8");
  CHECK(back.width() == 1280);
  for (std::size_t i = 0; i < camera.intrinsics().size(); ++i)
    CHECK(back.intrinsics()[i] == Approx(camera.intrinsics()[i]).epsilon(1e-12));
  CHECK((back.cam_from_ref.t - camera.cam_from_ref.t).norm() < 1e-12);
  CHECK_THROWS_AS(CameraModel::Read(dir / "missing.cameramodel"), UserError);
  CHECK_THROWS_AS(CameraModel("LENSMODEL_NOPE", {1, 2}, 10, 10), UserError);
}

TEST_CASE("poses compose and invert as rigid transforms", "[calib]") {
  Pose a, b;
  a.r = {0.1, 0.2, -0.3};
  a.t = {10, -20, 30};
  b.r = {-0.4, 0.1, 0.2};
  b.t = {1, 2, 3};
  const Eigen::Vector3d p(5, 6, 7);
  CHECK((a.Compose(b) * p - a * (b * p)).norm() < 1e-9);
  CHECK((a.Inverse() * (a * p) - p).norm() < 1e-9);
  // Looking at the centre: the sample centre is on the optical axis at the camera's distance.
  const Pose look = CamFromSampleLookingAtCentre(ArmPositionInSample(DegToRad(40), 1.0, 900));
  CHECK((look * Eigen::Vector3d::Zero() - Eigen::Vector3d(0, 0, 900)).norm() < 1e-9);
}

TEST_CASE("the corners cache is mrcal's vnlog: round trip and clear errors", "[calib]") {
  test::TempDir dir;
  const CameraModel camera = ExampleCamera();
  std::vector<BoardObservation> obs =
      SynthesizeCorners(camera, kBoard, GoodPoses(camera, 3, 1), 0.3, 2);
  obs[1].corners[5].z() = 0.5;       // decimation level 1
  obs[1].corners[6].z() = -1;        // not detected
  obs.push_back({"empty.png", {}});  // no board
  WriteCornersCache(dir / "c.vnl", obs);
  const std::vector<BoardObservation> back = ReadCornersCache(dir / "c.vnl", kBoard);
  REQUIRE(back.size() == obs.size());
  CHECK(!back[3].found());
  CHECK(back[1].corners[5].z() == 0.5);
  CHECK(back[1].corners[6].z() < 0);
  // Written with 4 decimals.
  CHECK(std::abs(back[0].corners[10].x() - obs[0].corners[10].x()) < 1e-4);
  // The wrong board size is named, with the file and line.
  try {
    ReadCornersCache(dir / "c.vnl", BoardSpec{9, 6, 25});
    FAIL("expected a UserError");
  } catch (const UserError& e) {
    CHECK(std::string(e.what()).find("9x6") != std::string::npos);
    CHECK(e.where().find("c.vnl:") != std::string::npos);
  }
}

TEST_CASE("OPENCV8 at 0.3 px noise: projection within the predicted uncertainty of the truth",
          "[calib]") {
  const CameraModel truth = ExampleCamera();
  const std::vector<Pose> poses = GoodPoses(truth, 40, 3);
  REQUIRE(poses.size() == 40);
  const std::vector<BoardObservation> obs = SynthesizeCorners(truth, kBoard, poses, 0.3, 7);
  const IntrinsicsSolution s = SolveIntrinsics(1280, 1024, kBoard, obs, IntrinsicsOptions{});
  // Residuals are the noise: per-coordinate RMS 0.3 px less the fitted share (sqrt((N-p)/N)).
  CHECK(s.rms_per_coordinate == Approx(0.3).epsilon(0.05));
  CHECK(s.rms_per_point == Approx(s.rms_per_coordinate * std::sqrt(2.0)).epsilon(1e-9));
  const BoardProblem truth_problem(truth, kBoard, obs, poses);
  const double distance = MedianBoardDistance(s.problem);
  const UncertaintyModel uncertainty(s.problem, s.selections, s.rms_per_coordinate);
  // Nine pixels over the imager. The error is a 2-D Gaussian of the predicted covariance if the
  // prediction is right: its squared Mahalanobis distance is chi-square with 2 dof, below 13.8
  // with probability 0.999.
  for (double fx : {0.1, 0.5, 0.9})
    for (double fy : {0.1, 0.5, 0.9}) {
      const Eigen::Vector2d q(fx * 1279, fy * 1023);
      const Eigen::Vector2d error =
          ReprojectThroughFrames(truth_problem, s.problem, q, distance) - q;
      const Eigen::Matrix2d cov = uncertainty.Covariance(q, distance);
      INFO("q " << q.transpose() << " error " << error.transpose() << " stdev "
                << std::sqrt(cov.trace()));
      CHECK(Mahalanobis2(error, cov) < 13.8);
    }
}

TEST_CASE("the predicted uncertainty matches the scatter of repeated noisy solves", "[calib]") {
  // 24 noise draws of one data set: the sample covariance of the projection error at a corner
  // pixel, compared with the prediction. With 24 draws the sample stdev has ~15% relative
  // scatter, so a ratio within [0.6, 1.5] fails only if the prediction is wrong.
  const CameraModel truth = ExampleCamera();
  const std::vector<Pose> poses = GoodPoses(truth, 20, 5);
  const Eigen::Vector2d q(150, 120);
  std::vector<Eigen::Vector2d> errors;
  double predicted = 0;
  for (int draw = 0; draw < 24; ++draw) {
    const std::vector<BoardObservation> obs =
        SynthesizeCorners(truth, kBoard, poses, 0.3, 100 + draw);
    IntrinsicsOptions o;
    o.board_warp = false;
    o.outlier_rejection = false;
    const IntrinsicsSolution s = SolveIntrinsics(1280, 1024, kBoard, obs, o);
    const BoardProblem truth_problem(truth, kBoard, obs, poses);
    const double distance = 450;
    errors.push_back(ReprojectThroughFrames(truth_problem, s.problem, q, distance) - q);
    if (draw == 0)
      predicted =
          std::sqrt(UncertaintyModel(s.problem, s.selections, 0.3).Covariance(q, distance).trace());
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& e : errors) mean += e / errors.size();
  double scatter = 0;
  for (const auto& e : errors) scatter += (e - mean).squaredNorm() / (errors.size() - 1);
  INFO("empirical " << std::sqrt(scatter) << " px, predicted " << predicted << " px");
  CHECK(std::sqrt(scatter) / predicted > 0.6);
  CHECK(std::sqrt(scatter) / predicted < 1.5);
}

TEST_CASE("extrinsics and the reference-to-view mapping are accurate at the sample", "[calib]") {
  // The gantry: camera 600 mm from the sample, a reference view straight down and views at
  // 20-65 degrees. Intrinsics from noisy boards; each view's pose from the board lying in the
  // sample plane (0.3 px noise); the reference pixels' positions in every view compared with the
  // truth over the board's area.
  const CameraModel truth = ExampleCamera();
  const std::vector<BoardObservation> calib_obs =
      SynthesizeCorners(truth, kBoard, GoodPoses(truth, 40, 3), 0.3, 7);
  const CameraModel solved =
      SolveIntrinsics(1280, 1024, kBoard, calib_obs, IntrinsicsOptions{}).problem.camera();
  // The target on the sample plane: a fine-pitch board (19 x 19 corners, 12.5 mm) of the same
  // 225 mm size: 361 corners fix a pose about twice as well as 100.
  const BoardSpec kTarget{19, 19, 12.5};
  const Pose board_from_sample = SampleFromBoard(kTarget).Inverse();
  struct View {
    double theta_deg, phi_deg;
  };
  const View views[] = {{0, 0}, {20, 30}, {45, 200}, {65, 120}};
  ReferenceView ref_truth{truth, {}}, ref_solved{solved, {}};
  std::vector<CalibratedView> truth_views, solved_views;
  int seed = 50;
  for (const View& v : views) {
    const Eigen::Vector3d cam =
        ArmPositionInSample(DegToRad(v.theta_deg), DegToRad(v.phi_deg), 600);
    const Pose cam_from_sample = CamFromSampleLookingAtCentre(cam);
    const std::vector<BoardObservation> obs = SynthesizeCorners(
        truth, kTarget, {cam_from_sample.Compose(board_from_sample.Inverse())}, 0.3, seed++);
    // The expected pose, as the gantry would predict it: 2 degrees and 5 mm off.
    Pose expected = cam_from_sample;
    expected.r += Eigen::Vector3d(0.02, -0.02, 0.01);
    expected.t += Eigen::Vector3d(5, -5, 5);
    const ExtrinsicsResult r = SolveCamFromSample(solved, kTarget, obs[0], expected);
    const Eigen::AngleAxisd dR(r.cam_from_sample.R().transpose() * cam_from_sample.R());
    const double dt = (r.cam_from_sample.Inverse().t - cam).norm();
    INFO("view theta " << v.theta_deg << ": rotation error " << RadToDeg(dR.angle())
                       << " deg, camera position error " << dt << " mm");
    // Tolerances: the tilt of a board facing the camera is its weakest parameter, seen only
    // through perspective: tilting by a moves the board's edges (L/2 = 112 mm off the axis at
    // d = 600 mm, f = 1000 px) by f (L/2)^2 a / d^2 = 35 px per radian, so 361 corners at 0.3 px
    // fix it to ~0.3 / (35 sqrt(361 / 4)) = 9e-4 rad = 0.05 deg, the camera position to
    // 600 x 9e-4 = 0.5 mm. Oblique views are better. 0.25 deg and 2 mm are ~4-5x those figures.
    CHECK(RadToDeg(dR.angle()) < 0.25);
    CHECK(dt < 2.0);
    CHECK(r.symmetry == 0);  // the ordering the truth uses was recovered
    truth_views.push_back({truth, cam_from_sample, {0, 0, 1000}});
    solved_views.push_back({solved, r.cam_from_sample, {0, 0, 1000}});
    if (v.theta_deg == 0) {
      ref_truth.cam_from_sample = cam_from_sample;
      ref_solved.cam_from_sample = r.cam_from_sample;
    }
  }
  // The reference pixels over the board (the sample) only.
  for (ReferenceView* ref : {&ref_truth, &ref_solved}) {
    ref->x0 = 500;
    ref->y0 = 380;
    ref->width = 280;
    ref->height = 260;
  }
  for (std::size_t v = 0; v < truth_views.size(); ++v) {
    const FloatPlanes a = ComputeCorrespondence(ref_truth, truth_views[v]);
    const FloatPlanes b = ComputeCorrespondence(ref_solved, solved_views[v]);
    double worst = 0, sum2 = 0;
    int compared = 0;
    for (std::size_t i = 0; i < a.planes.at("x").size(); ++i) {
      const float sx = a.planes.at("sample.x")[i], sy = a.planes.at("sample.y")[i];
      const bool on_board = std::abs(sx) < 110 && std::abs(sy) < 110;
      if (!on_board || a.planes.at("visible")[i] == 0) continue;
      const double dx = a.planes.at("x")[i] - b.planes.at("x")[i];
      const double dy = a.planes.at("y")[i] - b.planes.at("y")[i];
      worst = std::max(worst, std::hypot(dx, dy));
      sum2 += dx * dx + dy * dy;
      ++compared;
    }
    INFO("view " << v << ": mapping error RMS " << std::sqrt(sum2 / compared) << " worst " << worst
                 << " px over " << compared << " pixels");
    CHECK(compared > 10000);
    // The bar: under 0.1 px at the sample, met as the RMS over the sample (measured
    // 0.03-0.045 px). Single pixels at the sample's edges reach 0.13 px, where the pose's
    // tilt error grows with distance from the board centre; 0.2 px bounds them.
    CHECK(std::sqrt(sum2 / compared) < 0.1);
    CHECK(worst < 0.2);
  }
}

TEST_CASE("correspondence maps: directions and visibility by hand, EXR round trip", "[calib]") {
  const CameraModel camera = ExampleCamera();
  ReferenceView ref{camera, CamFromSampleLookingAtCentre({0, 0, 600})};
  ref.x0 = 600;
  ref.y0 = 480;
  ref.width = ref.height = 64;
  const Eigen::Vector3d light(300, 0, 400);
  const FloatPlanes map = ComputeCorrespondence(ref, {camera, ref.cam_from_sample, light});
  // The reference view maps to itself, and directions point at the light and camera.
  const int i = 20 * 64 + 30;
  CHECK(map.planes.at("x")[i] == Approx(630).margin(1e-3));
  CHECK(map.planes.at("y")[i] == Approx(500).margin(1e-3));
  const Eigen::Vector3d p(map.planes.at("sample.x")[i], map.planes.at("sample.y")[i], 0);
  const Eigen::Vector3d wi = (light - p).normalized();
  CHECK(map.planes.at("wi.x")[i] == Approx(wi.x()).margin(1e-6));
  CHECK(map.planes.at("wo.z")[i] ==
        Approx((Eigen::Vector3d(0, 0, 600) - p).normalized().z()).margin(1e-6));
  // A camera below the sample plane sees nothing of its face.
  const FloatPlanes below =
      ComputeCorrespondence(ref, {camera, CamFromSampleLookingAtCentre({0, 100, -600}), light});
  for (float v : below.planes.at("visible")) CHECK(v == 0);
  test::TempDir dir;
  WriteFloatPlanesExr(dir / "m.exr", map);
  const FloatPlanes back = ReadFloatPlanesExr(dir / "m.exr");
  CHECK(back.attributes.at("acqFormat") == "acq-correspondence-1");
  CHECK(back.planes.at("wi.x") == map.planes.at("wi.x"));
}

TEST_CASE("detectors find rendered boards' corners to a small fraction of a pixel", "[calib]") {
  const CameraModel camera = ExampleCamera();
  struct Case {
    BoardSpec board;
    Detector detector;
    // Blur 0.6 px and 1 grey level of noise on a 190-level step. OpenCV's cornerSubPix fits the
    // saddle point over a window of many edge pixels (a few hundredths of a pixel); mrgingham's
    // refinement is coarser (measured 0.07-0.13 px here). Either bound catches a renderer or
    // pixel-convention error: a half-pixel shift is 0.5 px per coordinate.
    double tolerance_px;
  };
  for (const Case& c : {Case{kBoard, Detector::kMrgingham, 0.2},
                        Case{BoardSpec{9, 6, 30}, Detector::kOpencv, 0.1}}) {
    BoardPoseSampling s;
    s.seed = 11;
    const std::vector<Pose> poses = SampleBoardPoses(camera, c.board, 4, s);
    int found_count = 0;
    for (const Pose& pose : poses) {
      const cv::Mat image = RenderBoard(camera, c.board, pose, BoardRenderOptions{});
      const BoardObservation found = DetectCorners(image, c.board, c.detector);
      if (!found.found()) continue;  // detectors miss some views; the count is checked below
      ++found_count;
      const BoardObservation exact = SynthesizeCorners(camera, c.board, {pose}, 0.0, 1)[0];
      // The detector may report any symmetric ordering: compare with the closest.
      double best = 1e9;
      for (const std::vector<int>& perm : BoardSymmetries(c.board)) {
        double sum = 0;
        int n = 0;
        for (std::size_t i = 0; i < perm.size(); ++i)
          if (found.corners[i].z() > 0) {
            sum += (found.corners[i].head<2>() - exact.corners[perm[i]].head<2>()).squaredNorm();
            ++n;
          }
        best = std::min(best, std::sqrt(sum / (2 * n)));
      }
      INFO("RMS per coordinate " << best);
      CHECK(best < c.tolerance_px);
    }
    CHECK(found_count >= 3);
  }
}

TEST_CASE("poor data sets are diagnosed with the figure that shows it", "[calib]") {
  const CameraModel truth = ExampleCamera();
  IntrinsicsOptions options;
  SECTION("too few boards: refused") {
    const auto obs = SynthesizeCorners(truth, kBoard, GoodPoses(truth, 2, 1), 0.3, 1);
    CHECK_THROWS_AS(SolveIntrinsics(1280, 1024, kBoard, obs, options), UserError);
  }
  SECTION("no board found (wrong board size): refused, pointing at --board") {
    std::vector<BoardObservation> obs(5);
    try {
      SolveIntrinsics(1280, 1024, kBoard, obs, options);
      FAIL("expected a UserError");
    } catch (const UserError& e) {
      CHECK(std::string(e.what()).find("--board") != std::string::npos);
    }
  }
  // The good set, for comparison.
  const auto good_obs = SynthesizeCorners(truth, kBoard, GoodPoses(truth, 30, 2), 0.3, 3);
  const CalibrationReport good =
      MakeReport(SolveIntrinsics(1280, 1024, kBoard, good_obs, options), good_obs, {});
  // Partly visible boards are normal in a good set (they reach the corners); nothing else warns.
  for (const std::string& w : good.warnings) CHECK(w.find("partly detected") != std::string::npos);
  CHECK(!good.refuse);
  // The report on 30 boards posed as `s` says.
  auto report_for = [&](const BoardPoseSampling& s) {
    const auto obs =
        SynthesizeCorners(truth, kBoard, SampleBoardPoses(truth, kBoard, 30, s), 0.3, 3);
    return MakeReport(SolveIntrinsics(1280, 1024, kBoard, obs, options), obs, {});
  };
  SECTION("every board facing the camera: warned, focal/distance confounded") {
    BoardPoseSampling s;
    s.max_tilt_deg = 3;
    s.seed = 4;
    const CalibrationReport r = report_for(s);
    REQUIRE(!r.warnings.empty());
    CHECK(r.warnings[0].find("facing the camera") != std::string::npos);
    CHECK(r.max_tilt_deg < 3.01);
  }
  SECTION("boards only in the centre: warned, uncertainty at the corners large") {
    BoardPoseSampling s;
    s.centre_spread = 0.1;
    s.min_distance_mm = 700;
    s.max_distance_mm = 900;
    s.seed = 5;
    const CalibrationReport r = report_for(s);
    bool coverage_warned = false;
    for (const std::string& w : r.warnings)
      coverage_warned |= w.find("cover only") != std::string::npos;
    CHECK(coverage_warned);
    CHECK(r.uncertainty_corner_px[0] > 10 * good.uncertainty_corner_px[0]);
    CHECK(r.refuse);  // worse than 1 px: no model is written without --force
  }
  SECTION("missing and partly detected boards are counted") {
    auto obs = good_obs;
    std::size_t whole = 0;  // a board seen whole, to hide 30 of its corners
    while (obs[whole].DetectedCorners() < kBoard.Corners()) ++whole;
    obs[whole == 0 ? 1 : 0].corners.clear();
    for (int i = 0; i < 30; ++i) obs[whole].corners[i].z() = -1;
    const CalibrationReport r =
        MakeReport(SolveIntrinsics(1280, 1024, kBoard, obs, options), obs, {});
    CHECK(!r.images[whole == 0 ? 1 : 0].found);
    CHECK(r.images[whole].detected == 70);
    bool missing_warned = false;
    for (const std::string& w : r.warnings)
      missing_warned |= w.find("no board found") != std::string::npos;
    CHECK(missing_warned);
  }
}

TEST_CASE("the lens-model ladder picks the simplest model the data support", "[calib]") {
  const std::vector<std::string> ladder = {"LENSMODEL_OPENCV4", "LENSMODEL_OPENCV5",
                                           "LENSMODEL_OPENCV8"};
  // A lens OPENCV4 describes exactly: the ladder stops at OPENCV4.
  CameraModel simple("LENSMODEL_OPENCV8", {1000, 995, 645.3, 508.1, -0.2, 0.05, 0, 0, 0, 0, 0, 0},
                     1280, 1024);
  const auto simple_obs = SynthesizeCorners(simple, kBoard, GoodPoses(simple, 40, 8), 0.3, 9);
  const LensModelChoice a = ChooseLensModel(1280, 1024, kBoard, simple_obs, {}, ladder);
  CHECK(a.rows[a.chosen].lensmodel == "LENSMODEL_OPENCV4");
  // A lens with a strong 6th-order term: OPENCV4 (to 4th order) is biased at the edges.
  CameraModel rich("LENSMODEL_OPENCV8", {1000, 995, 645.3, 508.1, -0.1, 0.0, 0, 0, 0.2, 0, 0, 0},
                   1280, 1024);
  const auto rich_obs = SynthesizeCorners(rich, kBoard, GoodPoses(rich, 40, 8), 0.3, 9);
  const LensModelChoice b = ChooseLensModel(1280, 1024, kBoard, rich_obs, {}, ladder);
  INFO("OPENCV4 cv " << b.rows[0].cv_diff_px << " px, OPENCV8 cv " << b.rows[2].cv_diff_px
                     << " px");
  CHECK(b.rows[b.chosen].lensmodel != "LENSMODEL_OPENCV4");
}

TEST_CASE("the ladder compares the halves only where both saw the board", "[calib]") {
  // Twelve boards, partly out of view: the cross-validation once compared the two halves'
  // splines over every cell either half saw, where one spline is extrapolated by its
  // regularization alone and did not project (`inf` in the ladder; `acq calibrate synthesize
  // --n 12 --partial-boards` printed inf for seeds 1, 2 and 3).
  const CameraModel camera = ExampleCamera();
  BoardPoseSampling sampling;  // as that command samples
  sampling.min_distance_mm = 300;
  sampling.max_distance_mm = 600;
  sampling.whole_board_in_view = false;
  sampling.seed = 2;
  const auto obs = SynthesizeCorners(camera, kBoard, SampleBoardPoses(camera, kBoard, 12, sampling),
                                     0.3, sampling.seed + 1000);
  const LensModelChoice c = ChooseLensModel(camera.width(), camera.height(), kBoard, obs, {},
                                            DefaultLadder(camera.width(), camera.intrinsics()[0]));
  for (const LadderRow& r : c.rows) {
    INFO(r.lensmodel << ": " << r.cv_diff_px << " px over " << r.cv_points << " points, "
                     << r.cv_diverged << " diverged");
    CHECK(std::isfinite(r.cv_diff_px));
    CHECK(r.cv_points > 0);
    CHECK(r.cv_diverged == 0);
  }
  REQUIRE(c.chosen >= 0);
}

TEST_CASE("a warped board: the warp is recovered and the residuals include it", "[calib]") {
  // A board bowed by 1.5 mm along x and -1.0 mm along y (a large but real print on foam),
  // 0.3 px noise. Solved with the warp, the residual per coordinate is the noise less what the
  // fit absorbs (sqrt((m - n) / m) of it, m measurements, n parameters: within 3%); reported
  // against a flat board, as the report once did, the same solve reads several times that.
  const CameraModel camera = ExampleCamera();
  const Eigen::Vector2d warp(1.5, -1.0);
  const auto obs = SynthesizeCorners(camera, kBoard, GoodPoses(camera, 30, 4), 0.3, 5, warp);
  IntrinsicsOptions options;
  const IntrinsicsSolution s = SolveIntrinsics(1280, 1024, kBoard, obs, options);
  INFO("warp " << s.problem.warp().transpose() << " mm, RMS " << s.rms_per_coordinate << " px");
  // The warp's standard error here is ~0.02 mm (mrcal's own uncertainty of x2, y2 at 30 boards).
  CHECK(std::abs(s.problem.warp().x() - warp.x()) < 0.1);
  CHECK(std::abs(s.problem.warp().y() - warp.y()) < 0.1);
  CHECK(s.rms_per_coordinate == Approx(0.3).epsilon(0.05));
  // The per-image figures of the report come from the same residuals.
  const CalibrationReport r = MakeReport(s, obs, {});
  for (const CalibrationReport::Image& im : r.images) CHECK(im.rms_px < 0.45);

  options.board_warp = false;  // a flat-board solve cannot explain the bow
  const IntrinsicsSolution flat = SolveIntrinsics(1280, 1024, kBoard, obs, options);
  INFO("flat-board RMS " << flat.rms_per_coordinate << " px");
  CHECK(flat.rms_per_coordinate > 1.3 * s.rms_per_coordinate);
}

TEST_CASE("a grid found inside a larger board is recognised, on any side", "[calib]") {
  // A 9x6 board. OpenCV's detectors can return an 8x6 or 7x5 part of it (the classic one drops
  // quads to fit the pattern asked for); the check looks one step beyond each side of the grid
  // found. The parts are cut from the whole board's detection, so the test does not depend on
  // which views a detector happens to mis-detect.
  const CameraModel camera = ExampleCamera();
  const BoardSpec printed{9, 6, 30};
  BoardPoseSampling s;
  s.seed = 11;
  int checked = 0;
  for (const Pose& pose : SampleBoardPoses(camera, printed, 3, s)) {
    const cv::Mat image = RenderBoard(camera, printed, pose, BoardRenderOptions{});
    const BoardObservation whole = DetectCorners(image, printed, Detector::kOpencv);
    if (!whole.found()) continue;
    ++checked;
    CHECK(!BoardExtendsBeyond(image, printed, whole));  // the whole board ends at its margin
    // Columns 0-7 of 9: the ninth lies to the right. Rows 1-5 of 6: the first lies above.
    BoardObservation left8, lower5;
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 9; ++i) {
        if (i < 8) left8.corners.push_back(whole.corners[j * 9 + i]);
        if (j >= 1) lower5.corners.push_back(whole.corners[j * 9 + i]);
      }
    // The detector's order may start at any corner; the side named is in its order, so the
    // test asks only that a side is found and that the message gives a larger size.
    CHECK(BoardExtendsBeyond(image, BoardSpec{8, 6, 30}, left8).has_value());
    CHECK(BoardExtendsBeyond(image, BoardSpec{9, 5, 30}, lower5).has_value());
  }
  CHECK(checked >= 2);
  // A 9x7 print taken as 9x6: the side beyond is a row (top or bottom in the grid's order).
  const BoardSpec taller{9, 7, 30};
  const cv::Mat image =
      RenderBoard(camera, taller, SampleBoardPoses(camera, taller, 1, s)[0], BoardRenderOptions{});
  const BoardObservation whole = DetectCorners(image, taller, Detector::kOpencv);
  REQUIRE(whole.found());
  BoardObservation part;
  part.corners.assign(whole.corners.begin(), whole.corners.begin() + 9 * 6);
  const auto side = BoardExtendsBeyond(image, printed, part);
  REQUIRE(side.has_value());
  CHECK((*side == BoardSide::kTop || *side == BoardSide::kBottom));
}
