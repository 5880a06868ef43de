#include "brdf/colour_outliers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "brdf/evaluation.h"
#include "brdf/group_merge.h"

namespace acq {
namespace {

constexpr double kMadToSigma = 1.4826;  // a normal distribution's sigma over its MAD
// Fewer neighbours seen at a view than this: no median to compare with, the observation kept.
constexpr int kMinCompared = 3;

// Each observation's departure from the median of the others it is compared with (its
// neighbours, or with none, the whole group) at the same view and ratio; NaN where not compared.
Eigen::MatrixXd Departures(const std::vector<std::vector<int>>& near,
                           const Eigen::MatrixXd& colour) {
  const Eigen::Index n = colour.rows(), columns = colour.cols();
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Constant(n, columns, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> group_median(std::size_t(columns), std::numeric_limits<double>::quiet_NaN());
  const bool alone =
      std::all_of(near.begin(), near.end(), [](const std::vector<int>& n) { return n.empty(); });
  for (Eigen::Index j = 0; alone && j < columns; ++j) {
    std::vector<double> all;
    for (Eigen::Index i = 0; i < n; ++i)
      if (std::isfinite(colour(i, j))) all.push_back(colour(i, j));
    if (int(all.size()) >= kMinCompared) group_median[std::size_t(j)] = Median(all);
  }
#pragma omp parallel for schedule(dynamic, 64)
  for (Eigen::Index i = 0; i < n; ++i) {
    std::vector<double> values;
    for (Eigen::Index j = 0; j < columns; ++j) {
      if (!std::isfinite(colour(i, j))) continue;
      double median = group_median[std::size_t(j)];
      if (!near[std::size_t(i)].empty()) {
        values.clear();
        for (int k : near[std::size_t(i)])
          if (std::isfinite(colour(k, j))) values.push_back(colour(k, j));
        median = int(values.size()) >= kMinCompared
                     ? MedianInPlace(values.data(), values.data() + values.size())
                     : std::numeric_limits<double>::quiet_NaN();
      }
      out(i, j) = colour(i, j) - median;
    }
  }
  return out;
}

}  // namespace

std::vector<std::uint8_t> ColourOutliers(const Eigen::MatrixX2d& field,
                                         const Eigen::MatrixXd& colour, int views) {
  const Eigen::Index n = colour.rows();
  std::vector<std::uint8_t> out(std::size_t(n) * std::size_t(views), 0);
  if (n == 0) return out;
  const Eigen::MatrixXd departure = Departures(FieldNeighbours(field, kColourNeighbours), colour);
  for (int v = 0; v < views; ++v)
    for (int ratio = 0; ratio < 2; ++ratio) {
      const Eigen::Index j = 2 * v + ratio;
      std::vector<double> size;
      for (Eigen::Index i = 0; i < n; ++i)
        if (std::isfinite(departure(i, j))) size.push_back(std::abs(departure(i, j)));
      if (size.empty()) continue;
      const double limit = kColourOutlierScales * (kMadToSigma * Median(size) + kColourScaleFloor);
      for (Eigen::Index i = 0; i < n; ++i)
        if (std::abs(departure(i, j)) > limit) out[std::size_t(i) * views + v] = 1;
    }
  return out;
}

}  // namespace acq
