// The demosaic study (issue 16): where demosaicing goes in the HDR chain and which method, on
// the simulated card through the simulated Bayer camera (its cross-talk, a warm light, the
// sensor's shot, read and quantisation noise, a 3-exposure bracket 3 stops apart).
//
//   A  merge the raw mosaic photosite by photosite, then demosaic the HDR image (acq/demosaic.h:
//      bilinear, malvar) -- what the pipeline does;
//   B  demosaic each exposure's 16-bit counts with OpenCV (bilinear, edge-aware; VNG takes 8-bit
//      counts only, so not here), then merge each channel.
//
// Each result, through the inverse of the camera's cross-talk and divided by a white Lambertian's
// rendering of the same light, is a reflectance per pixel, compared with the rendered truth's as
// CIEDE2000: over the card's interior and over its printed edges (pixels within 2 of another
// material, where zipper and false colour show), with and without the sensor's noise.
//   build/tests/bench_demosaic [size=480] [CSV]     (tools/study_demosaic.sh charts it)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "acq/demosaic.h"
#include "acq/hdr.h"
#include "brdf/evaluation.h"
#include "brdf/neural_brdf.h"
#include "calib/synthetic_board.h"
#include "core/colour.h"
#include "sim/instrument.h"
#include "sim/sim_gige_camera.h"

using namespace acq;

namespace {

constexpr Cfa kCfa = Cfa::kRGGB;

// OpenCV names its Bayer codes by another corner of the pattern than GenICam: found by
// demosaicing a mosaic whose red photosites alone are lit.
int OpencvCodeForRggb(int w, int h) {
  cv::Mat probe(h, w, CV_16U);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      probe.at<std::uint16_t>(y, x) = CfaChannel(kCfa, x, y) == 0 ? 1000 : 0;
  for (int code : {cv::COLOR_BayerBG2RGB, cv::COLOR_BayerGB2RGB, cv::COLOR_BayerRG2RGB,
                   cv::COLOR_BayerGR2RGB}) {
    cv::Mat rgb;
    cv::demosaicing(probe, rgb, code);
    const cv::Vec3w centre = rgb.at<cv::Vec3w>(h / 2, w / 2);
    if (centre[0] > 900 && centre[2] < 100) return code;
  }
  std::fprintf(stderr, "no OpenCV Bayer code matches RGGB\n");
  std::exit(1);
}

// Order B: each frame demosaiced by OpenCV, then each channel merged.
HdrImage DemosaicThenMerge(const std::vector<Frame>& frames, int code, bool edge_aware) {
  const int w = frames[0].width, h = frames[0].height;
  std::array<std::vector<Frame>, 3> channels;
  for (const Frame& f : frames) {
    cv::Mat mosaic(h, w, CV_16U, const_cast<std::uint16_t*>(f.pixels.data())), rgb;
    cv::demosaicing(mosaic, rgb,
                    edge_aware ? code + (cv::COLOR_BayerBG2RGB_EA - cv::COLOR_BayerBG2RGB) : code);
    for (int c = 0; c < 3; ++c) {
      Frame one = f;
      one.pixel_format = PixelFormat::kMono16;
      for (int i = 0; i < w * h; ++i) one.pixels[std::size_t(i)] = rgb.at<cv::Vec3w>(i)[c];
      channels[c].push_back(std::move(one));
    }
  }
  HdrImage out;
  out.width = w;
  out.height = h;
  out.channels = 3;
  out.flag.assign(std::size_t(w) * h, kHdrOk);
  for (int c = 0; c < 3; ++c) {
    const HdrImage merged = MergeBracket(channels[c], {});
    out.radiance.insert(out.radiance.end(), merged.radiance.begin(), merged.radiance.end());
    for (std::size_t i = 0; i < out.flag.size(); ++i) out.flag[i] |= merged.flag[i];
  }
  return out;
}

struct Scene {
  int w = 0, h = 0;
  std::vector<std::array<double, 3>> truth;  // reflectance (rec709 / white), per pixel
  std::vector<std::array<double, 3>> white;  // a white Lambertian's Rec. 709 radiance
  std::vector<int> label;                    // material, -1 off the card
  std::vector<float> mosaic;                 // camera RGB through the filter
};

Scene Render(int size) {
  static std::vector<NeuralBrdf> networks;
  for (const char* name : {"white-paint", "brass", "black-fabric", "pink-jasper"})
    networks.push_back(NeuralBrdf::Load(std::string(ACQ_DATA_DIR) + "/nbrdf/merl/" + name + ".h5"));
  sim::RenderScene card;
  card.kind = sim::RenderScene::Kind::kCard;
  card.sample_size_mm = 40;
  card.card = sim::MakeCardLayout(400, 400, card.sample_size_mm, 4, 1);
  for (const NeuralBrdf& n : networks) card.materials.push_back({&n, nullptr});
  const double f = 0.8 * size * 1000 / card.sample_size_mm;
  const calib::CameraModel model("LENSMODEL_PINHOLE", {f, f, (size - 1) / 2.0, (size - 1) / 2.0},
                                 size, size);
  const calib::Pose cam_from_sample = calib::CamFromSampleLookingAtCentre({0, 0, 1000});
  sim::PointLight light;
  light.position_mm = {500, 300, 800};
  light.intensity = 2e5;
  light.rgb = sim::kWarmLight;
  const sim::RadianceImage rec709 = sim::RenderRadiance(card, model, cam_from_sample, light, 1);
  sim::RenderScene board = card;
  board.kind = sim::RenderScene::Kind::kSpectralon;
  board.sample_size_mm = 100;
  board.spectralon_albedo = 1;
  const sim::RadianceImage white = sim::RenderRadiance(board, model, cam_from_sample, light, 1);
  Scene s;
  s.w = s.h = size;
  s.mosaic = sim::MosaicOf(rec709, sim::PlausibleCameraCrosstalk(), kCfa);
  const calib::Pose sample_from_cam = cam_from_sample.Inverse();
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::size_t i = std::size_t(y) * size + x;
      std::array<double, 3> t, wh;
      for (int c = 0; c < 3; ++c) {
        wh[c] = white.rgb[3 * i + c];
        t[c] = rec709.rgb[3 * i + c] / wh[c];
      }
      s.truth.push_back(t);
      s.white.push_back(wh);
      const Eigen::Vector3d ray = sample_from_cam.R() * model.Unproject(Eigen::Vector2d(x, y));
      const Eigen::Vector3d p = sample_from_cam.t + (-sample_from_cam.t.z() / ray.z()) * ray;
      s.label.push_back(card.card.LabelAt(p.head<2>()));
    }
  return s;
}

bool NearEdge(const Scene& s, int x, int y) {
  const int here = s.label[std::size_t(y) * s.w + x];
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int u = std::clamp(x + dx, 0, s.w - 1), v = std::clamp(y + dy, 0, s.h - 1);
      if (s.label[std::size_t(v) * s.w + u] != here) return true;
    }
  return false;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  const std::size_t k = std::min(v.size() - 1, std::size_t(p * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

}  // namespace

int main(int argc, char** argv) {
  const int size = argc > 1 ? std::max(64, std::atoi(argv[1])) : 480;
  const std::string csv = argc > 2 ? argv[2] : "";
  const Scene scene = Render(size);
  const Eigen::Matrix3d rec709_from_camera = sim::PlausibleCameraCrosstalk().inverse();
  const int code = OpencvCodeForRggb(size, size);
  sim::SensorModel sensor;
  const double brightest = *std::max_element(scene.mosaic.begin(), scene.mosaic.end());
  const double shortest_us = 0.8 * sensor.full_well_e / (brightest * sensor.quantum_scale);
  const double per_radiance = sensor.CountsPerRadianceUs(65535);  // HDR units per radiance

  struct Method {
    const char* order;
    const char* name;
    std::function<HdrImage(const std::vector<Frame>&)> run;
  };
  const std::vector<Method> methods = {
      {"merge, then demosaic", "bilinear",
       [](const std::vector<Frame>& f) {
         return Demosaic(MergeBracket(f, {}), DemosaicMethod::kBilinear);
       }},
      {"merge, then demosaic", "malvar",
       [](const std::vector<Frame>& f) {
         return Demosaic(MergeBracket(f, {}), DemosaicMethod::kMalvar);
       }},
      {"demosaic, then merge", "opencv bilinear",
       [&](const std::vector<Frame>& f) { return DemosaicThenMerge(f, code, false); }},
      {"demosaic, then merge", "opencv edge-aware",
       [&](const std::vector<Frame>& f) { return DemosaicThenMerge(f, code, true); }},
  };
  std::ofstream out_csv;
  if (!csv.empty()) {
    out_csv.open(csv);
    out_csv << "order,method,noise,region,median_de2000,p95_de2000,pixels\n";
  }
  std::printf(
      "demosaic study: %d x %d card (4 materials), RGGB, cross-talk, warm light, bracket "
      "%.0f/%.0f/%.0f us\n",
      size, size, shortest_us, 8 * shortest_us, 64 * shortest_us);
  std::printf("%-22s %-18s %-6s | interior median p95 | edges median p95\n", "order", "method",
              "noise");
  for (bool noise : {true, false}) {
    sensor.noise = noise;
    std::vector<Frame> frames;
    for (int e = 0; e < 3; ++e) {
      Frame f;
      f.width = f.height = size;
      f.pixel_format = PixelFormat::kBayerRG16;
      f.exposure_us = shortest_us * std::pow(8.0, e);
      f.pixels = sim::Expose(scene.mosaic, f.exposure_us, 0, 65535, sensor, 11 + e);
      frames.push_back(std::move(f));
    }
    for (const Method& m : methods) {
      const HdrImage hdr = m.run(frames);
      const std::size_t n = std::size_t(size) * size;
      std::vector<double> interior, edges;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const std::size_t i = std::size_t(y) * size + x;
          if (scene.label[i] < 0 || hdr.flag[i] != kHdrOk) continue;
          const Eigen::Vector3d camera(hdr.radiance[i], hdr.radiance[n + i],
                                       hdr.radiance[2 * n + i]);
          const Eigen::Vector3d rec709 = rec709_from_camera * camera / per_radiance;
          std::array<double, 3> r;
          for (int c = 0; c < 3; ++c) r[c] = rec709[c] / scene.white[i][c];
          const double de = DeltaE2000(LabFromLinearRec709(r), LabFromLinearRec709(scene.truth[i]));
          (NearEdge(scene, x, y) ? edges : interior).push_back(de);
        }
      std::printf("%-22s %-18s %-6s | %8.2f %6.2f | %8.2f %6.2f\n", m.order, m.name,
                  noise ? "on" : "off", Median(interior), Percentile(interior, 0.95), Median(edges),
                  Percentile(edges, 0.95));
      if (out_csv)
        for (const auto& [region, v] : {std::pair{"interior", &interior}, {"edges", &edges}})
          out_csv << '"' << m.order << "\"," << m.name << "," << (noise ? "on" : "off") << ","
                  << region << "," << Median(*v) << "," << Percentile(*v, 0.95) << "," << v->size()
                  << "\n";
    }
  }
}
