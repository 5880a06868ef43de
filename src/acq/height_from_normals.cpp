#include "acq/height_from_normals.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>

#include "core/error.h"
#include "core/sample_grid.h"

namespace acq {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kMaxSlope = std::tan(60 * kPi / 180);

// The height's gradient along the columns (x) and down the rows that the normal n implies.
cv::Vec2d GradientOf(const Eigen::Vector3f& n) {
  if (!n.allFinite() || !(n.z() > 0)) return {0, 0};
  // The slope along the sample's x and y, turned into the grid's columns and rows (the same
  // flip takes either way).
  const Eigen::Vector2d g = SampleGrid::SlopeOf(-n.x() / n.z(), -n.y() / n.z());
  return {std::clamp(g.x(), -kMaxSlope, kMaxSlope), std::clamp(g.y(), -kMaxSlope, kMaxSlope)};
}

// 2 pi times the signed frequency of DFT index i of n.
double Frequency(int i, int n) {
  return 2 * kPi * (i <= n / 2 ? i : i - n) / n;
}

}  // namespace

std::vector<float> HeightFromNormals(const std::vector<Eigen::Vector3f>& normals, int w, int h) {
  if (w < 1 || h < 1 || normals.size() != std::size_t(w) * std::size_t(h))
    throw UserError("height from normals", std::to_string(normals.size()) + " normals for " +
                                               std::to_string(w) + " x " + std::to_string(h));
  cv::Mat p(h, w, CV_64F), q(h, w, CV_64F);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const cv::Vec2d g = GradientOf(normals[std::size_t(y) * w + x]);
      p.at<double>(y, x) = g[0];
      q.at<double>(y, x) = g[1];
    }
  cv::Mat fp, fq;
  cv::dft(p, fp, cv::DFT_COMPLEX_OUTPUT);
  cv::dft(q, fq, cv::DFT_COMPLEX_OUTPUT);
  // Z = (-j u P - j v Q) / (u^2 + v^2), the mean (u = v = 0) left 0.
  cv::Mat fz(h, w, CV_64FC2);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = Frequency(x, w), v = Frequency(y, h), d = u * u + v * v;
      const cv::Vec2d a = fp.at<cv::Vec2d>(y, x), b = fq.at<cv::Vec2d>(y, x);
      // -j (u a + v b) for complex a, b: (re, im) -> (im, -re).
      const double re = u * a[0] + v * b[0], im = u * a[1] + v * b[1];
      fz.at<cv::Vec2d>(y, x) = d > 0 ? cv::Vec2d(im / d, -re / d) : cv::Vec2d(0, 0);
    }
  // The real part: at an even size's Nyquist frequency the spectrum above is not conjugate-
  // symmetric (its sign is ambiguous), and what it adds there is imaginary.
  cv::Mat z;
  cv::dft(fz, z, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_COMPLEX_OUTPUT);
  std::vector<float> height(std::size_t(w) * std::size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) height[std::size_t(y) * w + x] = float(z.at<cv::Vec2d>(y, x)[0]);
  return height;
}

}  // namespace acq
