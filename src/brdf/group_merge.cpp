#include "brdf/group_merge.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>

#include "brdf/evaluation.h"  // Median

namespace acq {
namespace {

// The field terms: the quadratic in the field coordinates scaled to [-1, 1] over all pixels.
// Cubic terms changed nothing measured (docs/reconstruction.md).
constexpr int kFieldTerms = 5;
using Terms = Eigen::Matrix<double, kFieldTerms, 1>;

std::vector<Terms> FieldTerms(const Eigen::MatrixX2d& field) {
  const Eigen::RowVector2d lo = field.colwise().minCoeff(), hi = field.colwise().maxCoeff();
  const Eigen::RowVector2d centre = 0.5 * (lo + hi), half = (0.5 * (hi - lo)).cwiseMax(1e-12);
  std::vector<Terms> terms(std::size_t(field.rows()));
  for (Eigen::Index i = 0; i < field.rows(); ++i) {
    const Eigen::RowVector2d u = (field.row(i) - centre).cwiseQuotient(half);
    terms[std::size_t(i)] << u.x(), u.y(), u.x() * u.x(), u.x() * u.y(), u.y() * u.y();
  }
  return terms;
}

// A group's sums over its pixels, z the field terms and f the feature: n, sum z, sum z z^T,
// sum f, sum z f^T and sum |f|^2. A pair's joint fit needs only these.
struct GroupSums {
  double n = 0, ff = 0;
  Eigen::VectorXd z, f;
  Eigen::MatrixXd zz, zf;
};

std::vector<GroupSums> SumsPerGroup(const Eigen::MatrixXd& features, const std::vector<Terms>& z,
                                    const std::vector<int>& label, int groups) {
  const Eigen::Index f = features.cols();
  std::vector<GroupSums> sums;
  sums.resize(std::size_t(groups));
  for (GroupSums& s : sums) {
    s.z.setZero(kFieldTerms), s.f.setZero(f);
    s.zz.setZero(kFieldTerms, kFieldTerms), s.zf.setZero(kFieldTerms, f);
  }
  for (std::size_t i = 0; i < label.size(); ++i) {
    if (label[i] < 0 || label[i] >= groups) continue;
    GroupSums& s = sums[std::size_t(label[i])];
    const Eigen::VectorXd fi = features.row(Eigen::Index(i)).transpose();
    s.n += 1, s.ff += fi.squaredNorm();
    s.z += z[i], s.f += fi;
    s.zz += z[i] * z[i].transpose(), s.zf += z[i] * fi.transpose();
  }
  return sums;
}

constexpr double kNoExtent = 1e-9;  // radians of the directions' offsets

}  // namespace

std::vector<std::vector<int>> FieldNeighbours(const Eigen::MatrixX2d& field, int count) {
  const Eigen::Index n = field.rows();
  std::vector<std::vector<int>> near(static_cast<std::size_t>(n));
  if (n == 0) return near;
  const Eigen::RowVector2d lo = field.colwise().minCoeff(), hi = field.colwise().maxCoeff();
  // A field of no extent (every pixel seeing the same directions) has no boundaries, and one
  // cell holding every pixel would cost n^2.
  if ((hi - lo).maxCoeff() < kNoExtent) return near;
  const Eigen::RowVector2d size = (hi - lo).cwiseMax(1e-15);
  // Cells of about count / 2 pixels each: the nine searched hold four times the neighbours kept.
  const int cells = std::max(1, int(std::sqrt(2.0 * double(n) / std::max(count, 1))));
  auto cell_of = [&](Eigen::Index i, int axis) {
    return std::clamp(int((field(i, axis) - lo[axis]) / size[axis] * cells), 0, cells - 1);
  };
  std::vector<std::vector<int>> grid(std::size_t(cells) * std::size_t(cells));
  for (Eigen::Index i = 0; i < n; ++i)
    grid[std::size_t(cell_of(i, 1) * cells + cell_of(i, 0))].push_back(int(i));
  std::vector<std::pair<double, int>> candidates;
  for (Eigen::Index i = 0; i < n; ++i) {
    candidates.clear();
    const int cx = cell_of(i, 0), cy = cell_of(i, 1);
    for (int y = std::max(0, cy - 1); y <= std::min(cells - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(cells - 1, cx + 1); ++x)
        for (int j : grid[std::size_t(y * cells + x)])
          if (j != i) candidates.push_back({(field.row(j) - field.row(i)).squaredNorm(), j});
    const std::size_t m = std::min<std::size_t>(std::size_t(std::max(count, 0)), candidates.size());
    std::partial_sort(candidates.begin(), candidates.begin() + std::ptrdiff_t(m), candidates.end());
    for (std::size_t c = 0; c < m; ++c) near[std::size_t(i)].push_back(candidates[c].second);
  }
  return near;
}

BoundaryStep StepAtBoundary(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field,
                            const std::vector<std::vector<int>>& near,
                            const std::vector<int>& label, int a, int b) {
  std::vector<double> across, within;
  for (std::size_t i = 0; i < label.size(); ++i) {
    if (label[i] != a && label[i] != b) continue;
    const int other_label = label[i] == a ? b : a;
    // The other group's nearest neighbour, and the neighbour of its own group at the most
    // nearly equal distance in the field: the drift between each pair is then alike.
    int own = -1, other = -1;
    for (int j : near[i])
      if (other < 0 && label[std::size_t(j)] == other_label) other = j;
    if (other < 0) continue;
    const double reach = (field.row(other) - field.row(Eigen::Index(i))).norm();
    double best = std::numeric_limits<double>::infinity();
    for (int j : near[i]) {
      if (label[std::size_t(j)] != label[i]) continue;
      const double d = std::abs((field.row(j) - field.row(Eigen::Index(i))).norm() - reach);
      if (d < best) best = d, own = j;
    }
    if (own < 0) continue;
    const Eigen::RowVectorXd f = features.row(Eigen::Index(i));
    across.push_back((f - features.row(other)).norm());
    within.push_back((f - features.row(own)).norm());
  }
  BoundaryStep step;
  step.pixels = int(across.size());
  if (step.pixels > 0) step.ratio = Median(across) / std::max(Median(within), 1e-300);
  return step;
}

namespace {

double Separation(const GroupSums& a, const GroupSums& b) {
  const double n = a.n + b.n;
  const int terms = n > 4 * (2 + kFieldTerms) ? kFieldTerms : 0, p = 2 + terms;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(p, p), R(p, a.f.size());
  A(0, 0) = a.n, A(1, 1) = b.n;
  R.row(0) = a.f.transpose(), R.row(1) = b.f.transpose();
  if (terms > 0) {
    A.block(2, 0, terms, 1) = a.z, A.block(2, 1, terms, 1) = b.z;
    A.block(0, 2, 1, terms) = a.z.transpose(), A.block(1, 2, 1, terms) = b.z.transpose();
    A.bottomRightCorner(terms, terms) = a.zz + b.zz;
    R.bottomRows(terms) = a.zf + b.zf;
  }
  A.diagonal().array() += 1e-9 * A.diagonal().maxCoeff();  // a field of no extent: terms 0
  const Eigen::MatrixXd beta = A.ldlt().solve(R);
  const Eigen::MatrixXd drift = beta.bottomRows(terms);  // terms x F, shared by the pair
  // A group's RMS residual from its sums: |f - m - drift^T z|^2 summed over its pixels, scaled
  // by n / (n - p) for the parameters fitted.
  auto scatter = [&](const GroupSums& s, int row) {
    const Eigen::VectorXd m = beta.row(row).transpose();
    double rss = s.ff - 2 * m.dot(s.f) + s.n * m.squaredNorm();
    if (terms > 0)
      rss += -2 * (drift.array() * s.zf.array()).sum() + 2 * m.dot(drift.transpose() * s.z) +
             (drift.array() * (s.zz * drift).array()).sum();
    return std::sqrt(std::max(rss, 0.0) / s.n * n / std::max(n - p, 1.0));
  };
  const double narrower = std::min(scatter(a, 0), scatter(b, 1));
  const double distance = (beta.row(0) - beta.row(1)).norm();
  return narrower > 0 ? distance / narrower : std::numeric_limits<double>::infinity();
}

}  // namespace

double GroupSeparation(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field,
                       const std::vector<int>& label, int a, int b) {
  const int groups = std::max(a, b) + 1;
  const std::vector<GroupSums> sums = SumsPerGroup(features, FieldTerms(field), label, groups);
  if (sums[std::size_t(a)].n == 0 || sums[std::size_t(b)].n == 0)
    return std::numeric_limits<double>::infinity();
  return Separation(sums[std::size_t(a)], sums[std::size_t(b)]);
}

int MergeOverlapping(const Eigen::MatrixXd& features, const Eigen::MatrixX2d& field, int groups,
                     std::vector<int>* label) {
  const std::vector<Terms> z = FieldTerms(field);
  const std::vector<std::vector<int>> near = FieldNeighbours(field);
  const bool any_neighbours =
      std::any_of(near.begin(), near.end(), [](const std::vector<int>& n) { return !n.empty(); });
  for (;;) {
    const std::vector<GroupSums> sums = SumsPerGroup(features, z, *label, groups);
    // The pair to merge: the closest under kMergeSeparation, else the one that meets another
    // with the smallest step under kBoundaryStep (ranked after every pair of the first kind).
    int merge_a = -1, merge_b = -1;
    double closest = std::numeric_limits<double>::infinity();
    for (int a = 0; a < groups; ++a)
      for (int b = a + 1; b < groups; ++b) {
        if (sums[std::size_t(a)].n == 0 || sums[std::size_t(b)].n == 0) continue;
        double rank = Separation(sums[std::size_t(a)], sums[std::size_t(b)]);
        if (!(rank < kMergeSeparation)) {  // not by separation: by the step where they meet
          rank = std::numeric_limits<double>::infinity();
          if (any_neighbours && closest >= kMergeSeparation) {
            const BoundaryStep step = StepAtBoundary(features, field, near, *label, a, b);
            if (step.pixels >= kMinBoundaryPixels && step.ratio < kBoundaryStep)
              rank = kMergeSeparation + step.ratio;
          }
        }
        if (rank < closest) closest = rank, merge_a = a, merge_b = b;
      }
    if (merge_a < 0) break;
    for (int& l : *label) {
      if (l == merge_b) l = merge_a;
      if (l == groups - 1) l = merge_b;  // keep the labels dense
    }
    --groups;
  }
  return groups;
}

bool SameGrouping(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  std::map<int, int> a_to_b, b_to_a;
  for (std::size_t i = 0; i < a.size(); ++i) {
    // emplace keeps the first pairing seen; any other pairing of either label differs.
    if (a_to_b.emplace(a[i], b[i]).first->second != b[i] ||
        b_to_a.emplace(b[i], a[i]).first->second != a[i])
      return false;
  }
  return true;
}

}  // namespace acq
