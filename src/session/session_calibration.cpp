#include "session/session_calibration.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/core.hpp>

#include "calib/correspondence.h"
#include "calib/detect_corners.h"
#include "calib/extrinsics.h"
#include "calib/intrinsics_report.h"
#include "calib/intrinsics_solve.h"
#include "calib/synthetic_board.h"
#include "core/angles.h"
#include "core/error.h"
#include "session/pose_hdr.h"

namespace acq {
namespace {

// An HDR board image for the detector: linear, scaled so that the bright squares sit near 200
// of 255 (the 99th percentile of the usable pixels), saturated pixels white.
cv::Mat ToneMapped(const HdrImage& hdr) {
  const std::vector<float> grey = hdr.Grey();
  std::vector<float> usable;
  for (std::size_t i = 0; i < grey.size(); ++i)
    if (hdr.flag[i] == kHdrOk) usable.push_back(grey[i]);
  float white = 1;
  if (!usable.empty()) {
    const std::size_t k = usable.size() * 99 / 100;
    std::nth_element(usable.begin(), usable.begin() + long(k), usable.end());
    white = std::max(usable[k], 1e-12f);
  }
  cv::Mat image(hdr.height, hdr.width, CV_8UC1);
  for (int y = 0; y < hdr.height; ++y)
    for (int x = 0; x < hdr.width; ++x) {
      const std::size_t i = std::size_t(y) * hdr.width + x;
      const double v = hdr.flag[i] == kHdrSaturated ? 255 : 200.0 * grey[i] / white;
      image.at<std::uint8_t>(y, x) = std::uint8_t(std::clamp(v, 0.0, 255.0));
    }
  return image;
}

calib::BoardSpec BoardOf(const Plan& plan) {
  return {plan.calibration.board_width_n, plan.calibration.board_height_n,
          plan.calibration.board_spacing_mm};
}

// Detects the board in every pose of `step`, each observation named after its pose.
std::vector<calib::BoardObservation> Detect(const std::map<int, PoseHdr>& poses, Step step,
                                            const calib::BoardSpec& board) {
  // Every board capture shows the board: a miss is worth OpenCV's full search (a bilinear
  // demosaic's zipper lost mrgingham 9 of 23 boards of the colour example; docs/colour.md).
  const calib::Detector detector = calib::Detector::kAutoInView;
  std::vector<calib::BoardObservation> out;
  for (const auto& [pose, p] : poses) {
    out.push_back(calib::DetectCorners(ToneMapped(p.hdr), board, detector));
    out.back().image = PoseName(step, pose);
  }
  return out;
}

void Intrinsics(const Plan& plan, const std::string& dir, const std::map<int, PoseHdr>& held,
                std::vector<calib::BoardObservation> obs, SessionCalibration* c) {
  c->intrinsics_captures = int(held.size());
  for (const calib::BoardObservation& o : obs) c->intrinsics_found += o.found();
  if (held.empty())
    throw UserError(dir, "no intrinsics captures in the session",
                    "run acqd again with the same plan to capture them");
  const HdrImage& any = held.begin()->second.hdr;
  calib::IntrinsicsOptions options;
  options.lensmodel = plan.calibration.lensmodel;
  const calib::IntrinsicsSolution solution = [&] {
    try {
      return calib::SolveIntrinsics(any.width, any.height, BoardOf(plan), obs, options);
    } catch (const UserError& e) {
      throw UserError(dir + "/calibration",
                      "cannot solve the intrinsics from the " + std::to_string(obs.size()) +
                          " held boards (" + std::to_string(c->intrinsics_found) +
                          " found): " + e.problem(),
                      "delete the intrinsics frames from the session (frames/intrinsics_*) and run "
                      "acqd again to recapture them with the whole board in view, or give "
                      "calibration.camera_model");
    }
  }();
  const calib::CalibrationReport report = calib::MakeReport(solution, obs, {});
  std::FILE* text = std::fopen((dir + "/calibration/intrinsics.txt").c_str(), "w");
  if (text) {
    calib::PrintReport(text, solution, report);
    std::fclose(text);
  }
  c->camera = solution.problem.camera();
  c->intrinsics_from = std::to_string(c->intrinsics_found) + " of " +
                       std::to_string(c->intrinsics_captures) + " held boards";
  c->intrinsics_rms_px = solution.rms_per_coordinate;
  c->uncertainty_centre_px = report.uncertainty_centre_px;
  c->uncertainty_worst_px = report.uncertainty_centre_px;
  for (double u : report.uncertainty_corner_px)
    c->uncertainty_worst_px = std::max(c->uncertainty_worst_px, u);
  c->warnings = report.warnings;
}

// The pose the arms' kinematics predict (the camera at its arm's end, looking at the centre).
calib::Pose KinematicPose(const Plan& plan, const ArmAngles& arms) {
  return calib::CamFromSampleLookingAtCentre(calib::ArmPositionInSample(
      arms.camera_theta, arms.camera_phi, plan.gantry.camera_distance_mm));
}

void Extrinsics(const Plan& plan, const calib::BoardSpec& board, Step step,
                const std::map<int, PoseHdr>& poses,
                const std::vector<calib::BoardObservation>& obs, SessionCalibration* c) {
  std::size_t k = 0;
  for (const auto& [pose, p] : poses) {
    const calib::BoardObservation& o = obs[k++];
    BoardPoseResult r;
    r.step = step;
    r.pose = pose;
    r.arms = p.arms;
    r.corners = o.DetectedCorners();
    // Fewer than half the corners: too little of the board to trust the pose.
    r.found = r.corners >= board.Corners() / 2;
    if (r.found) {
      const calib::Pose expected = KinematicPose(plan, p.arms);
      const calib::ExtrinsicsResult e = calib::SolveCamFromSample(c->camera, board, o, expected);
      r.cam_from_sample = e.cam_from_sample;
      r.rms_px = e.rms_px;
      r.angle_from_kinematics_deg = e.angle_from_expected_deg;
      r.shift_from_kinematics_mm = (e.cam_from_sample.Inverse().t - expected.Inverse().t).norm();
    } else {
      c->warnings.push_back(PoseName(step, pose) + ": board not found (" +
                            std::to_string(r.corners) + " corners); its views are left out");
    }
    c->boards.push_back(r);
  }
}

void WriteExtrinsics(const SessionCalibration& c, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw UserError(path, "cannot write the extrinsics", "check the session directory");
  std::fprintf(f,
               "# cam_from_sample per pose (mrcal rt: Rodrigues r, translation t in mm), from "
               "the board on the sample plane\n"
               "step\tpose\tfound\tcorners\trms_px\tr0\tr1\tr2\tt0\tt1\tt2\t"
               "angle_from_kinematics_deg\tshift_from_kinematics_mm\t"
               "light_theta_deg\tlight_phi_deg\tcamera_theta_deg\tcamera_phi_deg\n");
  for (const BoardPoseResult& b : c.boards) {
    const calib::Pose& p = b.cam_from_sample;
    const ArmAngles& a = b.arms;  // measured at the board's capture (for scoring, reprocessing)
    std::fprintf(f,
                 "%s\t%d\t%d\t%d\t%.4f\t%.9f\t%.9f\t%.9f\t%.6f\t%.6f\t%.6f\t%.4f\t%.3f\t"
                 "%.9f\t%.9f\t%.9f\t%.9f\n",
                 ToString(b.step), b.pose, int(b.found), b.corners, b.rms_px, p.r.x(), p.r.y(),
                 p.r.z(), p.t.x(), p.t.y(), p.t.z(), b.angle_from_kinematics_deg,
                 b.shift_from_kinematics_mm, RadToDeg(a.light_theta), RadToDeg(a.light_phi),
                 RadToDeg(a.camera_theta), RadToDeg(a.camera_phi));
  }
  std::fclose(f);
}

}  // namespace

const BoardPoseResult* SessionCalibration::PoseOf(Step step, int pose) const {
  const Step board = BoardStepFor(step);
  for (const BoardPoseResult& b : boards)
    if (b.step == board && b.pose == pose) return b.found ? &b : nullptr;
  return nullptr;
}

SessionCalibration CalibrateSession(const Plan& plan, const SessionFrames& session,
                                    double* hdr_seconds) {
  const std::string& dir = session.dir;
  std::filesystem::create_directories(dir + "/calibration");
  const calib::BoardSpec board = BoardOf(plan);
  SessionCalibration c;
  std::vector<calib::BoardObservation> all;
  if (plan.calibration.intrinsics_captures > 0) {
    const std::map<int, PoseHdr> held = MergeStep(Step::kIntrinsics, session, hdr_seconds);
    const std::vector<calib::BoardObservation> obs = Detect(held, Step::kIntrinsics, board);
    all.insert(all.end(), obs.begin(), obs.end());
    Intrinsics(plan, dir, held, obs, &c);
  } else {
    c.camera = calib::CameraModel::Read(plan.calibration.intrinsics_file);
    c.intrinsics_from = plan.calibration.intrinsics_file;
  }
  c.camera.Write(dir + "/calibration/camera.cameramodel");
  for (const Step step : {Step::kBoard, Step::kBoardValidation}) {
    if (step == Step::kBoardValidation && plan.validation.empty()) continue;
    const std::map<int, PoseHdr> poses = MergeStep(step, session, hdr_seconds);
    const std::vector<calib::BoardObservation> obs = Detect(poses, step, board);
    all.insert(all.end(), obs.begin(), obs.end());
    Extrinsics(plan, board, step, poses, obs, &c);
  }
  calib::WriteCornersCache(dir + "/calibration/corners.vnl", all);
  WriteExtrinsics(c, dir + "/calibration/extrinsics.tsv");
  // Later stages use the geometry as written, to its last bit (the files round it): the session
  // processed again from its files (`acq session process`) then computes what this run did, and
  // reuses its correspondence maps, which record their inputs (view_correspondence.h).
  const SessionCalibration written = ReadSessionCalibration(dir);
  c.camera = written.camera;
  for (std::size_t i = 0; i < c.boards.size(); ++i) {
    c.boards[i].cam_from_sample = written.boards[i].cam_from_sample;
    c.boards[i].arms = written.boards[i].arms;
  }
  return c;
}

SessionCalibration ReadSessionCalibration(const std::string& session_dir) {
  const std::string dir = session_dir + "/calibration";
  SessionCalibration c;
  c.camera = calib::CameraModel::Read(dir + "/camera.cameramodel");
  c.intrinsics_from = dir + "/camera.cameramodel";
  const std::string path = dir + "/extrinsics.tsv";
  std::ifstream in(path);
  if (!in)
    throw UserError(path, "cannot read the session's extrinsics",
                    "process from the calibration stage (--from calibration)");
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.empty() || line[0] == '#' || line.rfind("step\t", 0) == 0) continue;
    std::istringstream fields(line);
    BoardPoseResult b;
    int found = 0;
    Eigen::Vector3d r, t;
    std::string step;
    fields >> step >> b.pose >> found >> b.corners >> b.rms_px >> r.x() >> r.y() >> r.z() >>
        t.x() >> t.y() >> t.z() >> b.angle_from_kinematics_deg >> b.shift_from_kinematics_mm;
    const std::optional<Step> parsed = ParseStep(step);
    if (!fields || !parsed)
      throw UserError(path + ":" + std::to_string(line_number), "not an extrinsics row",
                      "process from the calibration stage (--from calibration)");
    b.step = *parsed;
    double arms[4];  // absent from files written before the arms were recorded
    b.arms_known = bool(fields >> arms[0] >> arms[1] >> arms[2] >> arms[3]);
    if (b.arms_known)
      b.arms = {DegToRad(arms[0]), DegToRad(arms[1]), DegToRad(arms[2]), DegToRad(arms[3])};
    b.found = found != 0;
    b.cam_from_sample.r = r;
    b.cam_from_sample.t = t;
    c.boards.push_back(b);
  }
  return c;
}

}  // namespace acq
