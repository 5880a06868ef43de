#include "brdf/pooled_model.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <sstream>

#include "brdf/colour_outliers.h"
#include "brdf/group_merge.h"
#include "brdf/log_mapping.h"
#include "brdf/pixel_rows.h"
#include "core/angles.h"
#include "core/error.h"
#include "core/merl_grid.h"

namespace acq {

const char* ReconstructionMethodName(ReconstructionMethod method) {
  return method == ReconstructionMethod::kPooled ? "pooled" : "independent";
}

std::optional<ReconstructionMethod> ParseReconstructionMethod(const std::string& name) {
  if (name == "independent") return ReconstructionMethod::kIndependent;
  if (name == "pooled") return ReconstructionMethod::kPooled;
  return std::nullopt;
}

void PooledOptions::Check() const {
  if (groups < 0 || groups > 1024) throw UserError("--groups", "must be in [0, 1024] (0: chosen)");
  if (max_groups < 1 || max_groups > 1024) throw UserError("--max-groups", "must be in [1, 1024]");
  if (sample_pixels < 64 || sample_pixels > (1 << 20))
    throw UserError("--sample-pixels", "must be in [64, 1048576]");
  CheckDesignSigma(design_sigma_deg, "--design-sigma-deg");
}

void CheckDesignSigma(double deg, const std::string& where) {
  if (!(deg >= 0 && deg <= kMaxDesignSigmaDeg))
    throw UserError(where, "must be in [0, " + std::to_string(int(kMaxDesignSigmaDeg)) +
                               "] degrees (0: every pixel alike)");
}

void PooledModel::Feature(const float* c, int k, double* feature) const {
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < features; ++i)
      feature[ch * features + i] = i < k ? weight[i] * c[ch * k + i] : 0.0;
}

double PooledModel::Distance(const float* a, int ka, const float* b, int kb) const {
  double sum = 0;
  const int n = std::max(ka, kb);
  for (int ch = 0; ch < 3; ++ch)
    for (int i = 0; i < n && i < int(weight.size()); ++i) {
      const double d = (i < ka ? a[ch * ka + i] : 0.0) - (i < kb ? b[ch * kb + i] : 0.0);
      sum += weight[i] * weight[i] * d * d;
    }
  return std::sqrt(sum / 3);
}

std::vector<int> PooledModel::NearestGroups(const std::vector<double>& feature, int m) const {
  std::vector<std::pair<double, int>> by_distance;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    double d = 0;
    for (std::size_t i = 0; i < feature.size(); ++i) {
      const double e = feature[i] - groups[g].feature[i];
      d += e * e;
    }
    by_distance.push_back({d, int(g)});
  }
  m = std::min(m, int(by_distance.size()));
  std::partial_sort(by_distance.begin(), by_distance.begin() + m, by_distance.end());
  std::vector<int> nearest;
  for (int i = 0; i < m; ++i) nearest.push_back(by_distance[i].second);
  return nearest;
}

std::string PooledModel::Summary() const {
  std::ostringstream s;
  s.precision(4);
  s << "pooled model: " << groups.size() << " groups from " << sample_pixels
    << " sample pixels, centres weighted to the design by " << design_sigma_deg
    << " deg; leave-one-view-out RMS " << held_out_rms << " (independent "
    << independent_held_out_rms << ")\n  groups tried (held-out RMS):";
  for (const Trial& t : selection) s << " " << t.groups << ":" << t.held_out_rms;
  s << "\n";
  if (dropped_held_out_rms > 0)
    s << "  no groups kept: their held-out RMS " << dropped_held_out_rms
      << " does not beat every pixel alone by 1%; every pixel is solved alone\n";
  for (std::size_t g = 0; g < groups.size(); ++g)
    s << "  group " << g << ": " << groups[g].sample_pixels << " sample pixels (centre from "
      << groups[g].centre_members << ", " << groups[g].effective_pixels << " effective), k_c "
      << groups[g].centre_components << ", eta " << groups[g].centre_eta << ", "
      << groups[g].colour_outliers << " observations left out as colour fringes, misfit limit "
      << groups[g].misfit_limit << ", strength " << groups[g].strength << ", held-out RMS "
      << groups[g].held_out_rms << "\n";
  return s.str();
}

namespace {

// A larger model (more groups, more centre components) is taken only when it lowers the
// held-out error by more than this fraction: model no more than the data can tell apart.
constexpr double kSizeTolerance = 0.01;
// For the number of groups a smaller margin: the merging of overlapping groups (below) guards
// against splitting a material, and a material covering a few percent of the sample moves the
// sample's total error by little more than this when it gets its own group.
constexpr double kGroupTolerance = 0.001;
constexpr int kMinUsableSample = 16;
constexpr int kFeatureComponents = 10;  // per channel: the components that carry most energy
// Eigenvalues of a group's normal matrix below this fraction of its largest count as zero
// (RowRank): far above the rounding of sums of identical rows (1e-16), far below any field's
// spread (1e-5 at 0.1 degree).
constexpr double kRankTolerance = 1e-9;

// One sample pixel, prepared once: its used rows with every centre component, its mapped
// observations, and the eigendecomposition of its k-column normal matrix, which turns every
// ridge solve and leave-one-out error for any strength into a few vector operations.
struct SamplePixel {
  Eigen::MatrixXf rows;   // n x K
  Eigen::MatrixXd y;      // n x 3, mapped, less the mean
  Eigen::VectorXd eigen;  // k eigenvalues of Q_k^T Q_k
  Eigen::MatrixXd z;      // n x k: Q_k in the eigenvectors' frame
  Eigen::MatrixXd vectors;
  std::vector<int> view;  // the view of each row
  std::vector<double> feature;
  double independent_sq = 0;  // leave-one-view-out squared error of the independent solve
  double design_offset = 0;   // RMS angle (rad) of its directions from the sample's mean ones
  // Where it lies in the field: the mean offset (x, y) of its light and camera directions from
  // the sample's mean ones, a smooth one-to-one function of its position on the sample (a point
  // moved by P turns every direction by about -P / distance, less its part along the direction).
  Eigen::Vector2d field{0, 0};
};

// The strengths tried: the independent solve's eta times powers of 4, and the centre itself.
// Never below eta: a ridge towards a centre fitted from the same views counts the pixel's data
// twice, and the held-out views, which reward interpolating between the views more than the
// grid's extrapolation away from them, preferred that; the map got worse (black fabric on the
// card at 0 degrees: 0.169 with strengths down to eta / 16, 0.144 alone).
std::vector<double> StrengthGrid(double eta) {
  const double base = eta > 0 ? eta : kDefaultEta;
  std::vector<double> grid;
  for (int j = 0; j <= 7; ++j) grid.push_back(base * std::pow(4.0, j));
  grid.push_back(std::numeric_limits<double>::infinity());
  return grid;
}

// The independent solve's exact leave-one-view-out squared error (summed over views and
// channels) at strength eta: e_v = r_v / (1 - h_v).
double IndependentLeaveOneOut(const SamplePixel& p, double eta) {
  const Eigen::VectorXd inv = (p.eigen.array() + eta).inverse();
  const Eigen::MatrixXd r =
      p.y - p.z * ((p.z.transpose() * p.y).array().colwise() * inv.array()).matrix();
  const Eigen::VectorXd h = p.z.array().square().matrix() * inv;
  return (r.array().colwise() / (1.0 - h.array())).square().sum();
}

// The pooled solve's leave-one-view-out squared errors at each strength, view v judged against
// `centres[v]` (K x 3, first kc used): the group's centre fitted without view v, or the one from
// every view. The ridge is linear in its target y - Q c, so the left-out residual is still exact
// from the full fit: with P = (I - H) Q and r0 = (I - H) y,
//   e_v = (r0_v - P_v c_v) / (1 - h_v).
void PooledLeaveOneOut(const SamplePixel& p, const std::vector<Eigen::MatrixXd>& centres, int kc,
                       const std::vector<double>& strengths, double* out) {
  const int n = int(p.view.size());
  const Eigen::MatrixXd q = p.rows.leftCols(kc).cast<double>();
  Eigen::MatrixXd qc(n, 3);  // row v: q_v . c_-v per channel
  for (int r = 0; r < n; ++r) qc.row(r) = q.row(r) * centres[p.view[r]].topRows(kc);
  const Eigen::MatrixXd zty = p.z.transpose() * p.y, ztq = p.z.transpose() * q;
  const Eigen::MatrixXd z2 = p.z.array().square();
  for (std::size_t s = 0; s < strengths.size(); ++s) {
    if (std::isinf(strengths[s])) {  // the pixel is its centre
      out[s] = (p.y - qc).squaredNorm();
      continue;
    }
    const Eigen::VectorXd inv = (p.eigen.array() + strengths[s]).inverse();
    const Eigen::MatrixXd r0 = p.y - p.z * (zty.array().colwise() * inv.array()).matrix();
    const Eigen::MatrixXd pq = q - p.z * (ztq.array().colwise() * inv.array()).matrix();
    const Eigen::VectorXd h = z2 * inv;
    double sum = 0;
    for (int r = 0; r < n; ++r) {
      const Eigen::RowVector3d e = r0.row(r) - pq.row(r) * centres[p.view[r]].topRows(kc);
      sum += e.squaredNorm() / ((1.0 - h(r)) * (1.0 - h(r)));
    }
    out[s] = sum;
  }
}

// Each view's mean light and camera direction over the given observations: on a sample spread
// over the image, the directions at its centre, which the plan's directions were chosen for.
void MeanDirections(const PixelObservations& obs, std::vector<Eigen::Vector3d>* light,
                    std::vector<Eigen::Vector3d>* camera) {
  light->assign(obs.views, Eigen::Vector3d::Zero());
  camera->assign(obs.views, Eigen::Vector3d::Zero());
  for (int i = 0; i < obs.pixels; ++i)
    for (int v = 0; v < obs.views; ++v) {
      const Eigen::Vector3d l = obs.light[obs.At(i, v)].cast<double>();
      const Eigen::Vector3d c = obs.camera[obs.At(i, v)].cast<double>();
      if (l.allFinite() && c.allFinite()) (*light)[v] += l, (*camera)[v] += c;
    }
  for (int v = 0; v < obs.views; ++v) {
    (*light)[v].normalize();
    (*camera)[v].normalize();
  }
}

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

std::vector<SamplePixel> PrepareSample(const BasisView& basis, const PixelObservations& obs,
                                       const PixelSolveOptions& solve, int K,
                                       const PooledModel& model) {
  const int k = solve.components;
  std::vector<Eigen::Vector3d> mean_light, mean_camera;
  MeanDirections(obs, &mean_light, &mean_camera);
  std::vector<SamplePixel> out(obs.pixels);
  std::vector<std::uint8_t> usable(obs.pixels, 0);
  const double eta = std::max(solve.eta, 1e-9);
#pragma omp parallel
  {
    ViewRows rows;
#pragma omp for schedule(dynamic, 16)
    for (int i = 0; i < obs.pixels; ++i) {
      rows.Sample(basis, obs, i, K, solve.lookup);
      SamplePixel& p = out[i];
      for (int v = 0; v < obs.views; ++v) {
        const float* rgb = &obs.rgb[3 * obs.At(i, v)];
        if (rows.ok[v] && std::isfinite(rgb[0]) && std::isfinite(rgb[1]) && std::isfinite(rgb[2]))
          p.view.push_back(v);
      }
      const int n = int(p.view.size());
      if (n < solve.MinObservations()) continue;
      double offset = 0;
      for (int v : p.view) {
        const Eigen::Vector3d l = obs.light[obs.At(i, v)].cast<double>();
        const Eigen::Vector3d c = obs.camera[obs.At(i, v)].cast<double>();
        offset += std::pow(Angle(l, mean_light[v]), 2) + std::pow(Angle(c, mean_camera[v]), 2);
        p.field += (l - mean_light[v] + c - mean_camera[v]).head<2>() / double(n);
      }
      p.design_offset = std::sqrt(offset / (2.0 * n));
      if (!std::isfinite(p.design_offset)) p.design_offset = kPi;  // the least trusted
      if (!p.field.allFinite()) p.field.setZero();
      p.rows.resize(n, K);
      p.y.resize(n, 3);
      for (int r = 0; r < n; ++r) {
        const int v = p.view[r];
        p.rows.row(r) = rows.rows.row(v).cast<float>();
        const BasisSample& s = rows.samples[v];
        const float* rgb = &obs.rgb[3 * obs.At(i, v)];
        for (int ch = 0; ch < 3; ++ch) p.y(r, ch) = MapBrdf(rgb[ch], s.cos_weight, s.ref) - s.mean;
      }
      const Eigen::MatrixXd qk = p.rows.leftCols(k).cast<double>();
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(qk.transpose() * qk);
      p.eigen = es.eigenvalues().cwiseMax(0.0);
      p.vectors = es.eigenvectors();
      p.z = qk * p.vectors;
      p.independent_sq = IndependentLeaveOneOut(p, eta);
      const Eigen::MatrixXd a = (p.z.transpose() * p.y).array().colwise() / (p.eigen.array() + eta);
      const Eigen::MatrixXd c = p.vectors * a;  // k x 3
      std::vector<float> coefficients(3 * k);
      for (int ch = 0; ch < 3; ++ch)
        for (int j = 0; j < k; ++j) coefficients[ch * k + j] = float(c(j, ch));
      p.feature.resize(3 * model.features);
      model.Feature(coefficients.data(), k, p.feature.data());
      usable[i] = std::isfinite(p.independent_sq) && c.allFinite();
    }
  }
  std::vector<SamplePixel> kept;
  for (int i = 0; i < obs.pixels; ++i)
    if (usable[i]) kept.push_back(std::move(out[i]));
  return kept;
}

double SquaredDistance(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

// Each group's mean feature over the pixels labelled with it, and (optional) its pixel count.
std::vector<std::vector<double>> GroupMeans(const std::vector<SamplePixel>& pixels,
                                            const std::vector<int>& label, int groups,
                                            std::vector<int>* count = nullptr) {
  std::vector<std::vector<double>> mean(groups, std::vector<double>(pixels[0].feature.size(), 0));
  std::vector<int> n(groups, 0);
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    ++n[label[i]];
    for (std::size_t j = 0; j < mean[0].size(); ++j) mean[label[i]][j] += pixels[i].feature[j];
  }
  for (int g = 0; g < groups; ++g)
    for (double& v : mean[g]) v /= std::max(n[g], 1);
  if (count) *count = std::move(n);
  return mean;
}

// k-means++ seeding, then Lloyd's iterations until no pixel changes group (at most 50); an
// emptied group is re-seeded at the pixel farthest from its centroid. Deterministic for a seed.
std::vector<int> KMeans(const std::vector<SamplePixel>& pixels, int groups, std::uint64_t seed) {
  const int n = int(pixels.size());
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> centroids(
      1, pixels[std::uniform_int_distribution<int>(0, n - 1)(rng)].feature);
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  while (int(centroids.size()) < groups) {
    double total = 0;
    for (int i = 0; i < n; ++i) {
      nearest[i] = std::min(nearest[i], SquaredDistance(pixels[i].feature, centroids.back()));
      total += nearest[i];
    }
    double pick = std::uniform_real_distribution<double>(0, total)(rng);
    int chosen = n - 1;
    for (int i = 0; i < n; ++i)
      if ((pick -= nearest[i]) <= 0) {
        chosen = i;
        break;
      }
    centroids.push_back(pixels[chosen].feature);
  }
  std::vector<int> label(n, -1);
  for (int iteration = 0; iteration < 50; ++iteration) {
    bool changed = false;
#pragma omp parallel for reduction(|| : changed)
    for (int i = 0; i < n; ++i) {
      int best = 0;
      double best_d = std::numeric_limits<double>::infinity();
      for (int g = 0; g < groups; ++g) {
        const double d = SquaredDistance(pixels[i].feature, centroids[g]);
        if (d < best_d) best_d = d, best = g;
      }
      changed = changed || best != label[i];
      label[i] = best;
    }
    if (!changed) break;
    std::vector<int> count;
    std::vector<std::vector<double>> mean = GroupMeans(pixels, label, groups, &count);
    for (int g = 0; g < groups; ++g) {
      if (count[g] > 0) {
        centroids[g] = std::move(mean[g]);
        continue;
      }
      int far = 0;
      double far_d = -1;
      for (int i = 0; i < n; ++i) {
        const double d = SquaredDistance(pixels[i].feature, centroids[label[i]]);
        if (d > far_d) far_d = d, far = i;
      }
      centroids[g] = pixels[far].feature;
      label[far] = g;
    }
  }
  return label;
}

// Each member's weight in its group's centre, summing to one: exp(-d^2 / 2 sigma^2), d how far
// (RMS angle) the member's directions lie beyond those of the member nearest the design. Tried:
// widening sigma for a group whose nearest member is d0 from the design (hypot(sigma, d0)), so
// that a piece of an ink cut off at the field's edge is weighted more alike: 8 forced groups
// 0.403 -> 0.396, but the chosen model on the card at 10 degrees 0.319 -> 0.324 (10% noise:
// 0.286 -> 0.317); not kept. sigma is widened until the weights amount to at least
// kDesignMinEffective pixels (or the group's size): a centre never rests on a handful of pixels,
// one of which may be misregistered.
constexpr double kDesignMinEffective = 16;
std::vector<double> DesignWeights(const std::vector<SamplePixel>& pixels,
                                  const std::vector<int>& members, double sigma) {
  std::vector<double> w(members.size(), 1.0 / double(std::max<std::size_t>(members.size(), 1)));
  if (sigma <= 0) return w;  // every pixel alike
  double nearest = std::numeric_limits<double>::infinity();
  for (int i : members) nearest = std::min(nearest, pixels[i].design_offset);
  const double min_effective = std::min(kDesignMinEffective, double(members.size()));
  // Each widening multiplies sigma by 1.25; 100 of them take it past any angle (5e9 times).
  for (int widening = 0; widening < 100; ++widening, sigma *= 1.25) {
    double sum = 0, sum_sq = 0;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const double d = (pixels[members[m]].design_offset - nearest) / sigma;
      w[m] = std::exp(-0.5 * d * d);
      sum += w[m], sum_sq += w[m] * w[m];
    }
    for (double& x : w) x /= sum;
    if (sum * sum >= 0.999 * min_effective * sum_sq) return w;
  }
  std::fill(w.begin(), w.end(), 1.0 / double(members.size()));
  return w;
}

// A group's normal equations per view, over its pixels' rows (first K components), as a weighted
// mean over its pixels: a centre from all views, or from all but one, is then one small solve.
// With the independent solve's eta the centre is regularised as one pixel is: at zero field of
// view (every pixel seeing the same directions) it is the independent solve of the pixels' mean.
// Counting pixels as independent evidence (the plain sum, or one observation per distinct bin)
// let the centre fit the basis's out-of-space residual, shared by the pixels of an ink at nearly
// the same directions, and extrapolate badly. The weights (DesignWeights) favour the pixels whose
// directions are nearest the plan's: those were optimised for the error over the whole grid,
// while a fit to every pixel's directions alike spends the basis on the near-field spread of
// the observations (most of it through the specular peak, where the basis misses most); the
// card at 4 degrees, white paint: 0.362 with every pixel alike, 0.277 weighted
// (docs/reconstruction.md, "Pooled").
// The observations of a group's pixels whose colour departs from their neighbours' at the same
// view (colour_outliers.h: fringes at ink edges), members x views.
std::vector<std::uint8_t> GroupColourOutliers(const std::vector<SamplePixel>& pixels,
                                              const std::vector<int>& members, int views) {
  const Eigen::Index n = Eigen::Index(members.size());
  Eigen::MatrixX2d field(n, 2);
  Eigen::MatrixXd colour =
      Eigen::MatrixXd::Constant(n, 2 * views, std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index m = 0; m < n; ++m) {
    const SamplePixel& p = pixels[std::size_t(members[std::size_t(m)])];
    field.row(m) = p.field.transpose();
    for (int r = 0; r < int(p.view.size()); ++r) {
      colour(m, 2 * p.view[r]) = p.y(r, 0) - p.y(r, 1);
      colour(m, 2 * p.view[r] + 1) = p.y(r, 2) - p.y(r, 1);
    }
  }
  return ColourOutliers(field, colour, views);
}

struct ViewStats {
  std::vector<Eigen::MatrixXd> a, b;  // per view: Q^T Q (K x K), Q^T y (K x 3), weighted means
  std::vector<double> s;              // per view: |y|^2, weighted mean
  Eigen::MatrixXd a_all, b_all;
  double effective_pixels = 0;  // (sum w)^2 / sum w^2
  int left_out = 0;             // observations left out as colour fringes (GroupColourOutliers)
  // leave_out_fringes: PooledOptions::leave_out_colour_fringes.
  ViewStats(const std::vector<SamplePixel>& pixels, const std::vector<int>& members, int K,
            int views, double design_sigma, bool leave_out_fringes)
      : a(views, Eigen::MatrixXd::Zero(K, K)), b(views, Eigen::MatrixXd::Zero(K, 3)), s(views, 0) {
    const std::vector<double> weights = DesignWeights(pixels, members, design_sigma);
    const std::vector<std::uint8_t> fringe =
        leave_out_fringes ? GroupColourOutliers(pixels, members, views)
                          : std::vector<std::uint8_t>(members.size() * std::size_t(views), 0);
    double sum_sq = 0;
    for (double w : weights) sum_sq += w * w;
    effective_pixels = sum_sq > 0 ? 1.0 / sum_sq : 0.0;
    // Per view, the weight of the observations made and of those kept: a fringe's weight goes to
    // the rest of its view. Kept where it was lost, the weight nearest the design (at the ink's
    // edge where inks meet at the sample's centre) went to the ridge instead: one dark material
    // with a fringed band through the centre gave a centre 46% worse than from clean data.
    std::vector<double> made(std::size_t(views), 0), kept(std::size_t(views), 0);
    for (std::size_t m = 0; m < members.size(); ++m) {
      const SamplePixel& p = pixels[members[m]];
      const double w = weights[m];
      for (int r = 0; r < int(p.view.size()); ++r) {
        const int v = p.view[r];
        made[std::size_t(v)] += w;
        if (fringe[m * std::size_t(views) + std::size_t(v)]) {
          ++left_out;
          continue;
        }
        kept[std::size_t(v)] += w;
        const Eigen::VectorXd q = p.rows.row(r).head(K).transpose().cast<double>();
        a[v].selfadjointView<Eigen::Lower>().rankUpdate(q, w);
        b[v].noalias() += w * q * p.y.row(r);
        s[v] += w * p.y.row(r).squaredNorm();
      }
    }
    a_all = Eigen::MatrixXd::Zero(K, K), b_all = Eigen::MatrixXd::Zero(K, 3);
    for (int v = 0; v < views; ++v) {
      if (kept[std::size_t(v)] > 0 && kept[std::size_t(v)] < made[std::size_t(v)]) {
        const double scale = made[std::size_t(v)] / kept[std::size_t(v)];
        a[v] *= scale, b[v] *= scale, s[v] *= scale;
      }
      a[v] = a[v].selfadjointView<Eigen::Lower>();
      a_all += a[v];
      b_all += b[v];
    }
  }
  // The centre (K x 3, zero past kc) from every view but `without` (-1: from all).
  Eigen::MatrixXd Centre(int kc, double eta, int without = -1) const {
    Eigen::MatrixXd m = a_all.topLeftCorner(kc, kc);
    Eigen::MatrixXd rhs = b_all.topRows(kc);
    if (without >= 0) {
      m -= a[without].topLeftCorner(kc, kc);
      rhs -= b[without].topRows(kc);
    }
    m.diagonal().array() += std::max(eta, 1e-9);
    Eigen::MatrixXd centre = Eigen::MatrixXd::Zero(a_all.rows(), 3);
    centre.topRows(kc) = m.ldlt().solve(rhs);
    return centre;
  }
  std::vector<Eigen::MatrixXd> CentresWithoutEachView(int kc, double eta) const {
    std::vector<Eigen::MatrixXd> out;
    for (int v = 0; v < int(a.size()); ++v) out.push_back(Centre(kc, eta, v));
    return out;
  }
};

// The centre's held-out error: each view left out of all the group's pixels at once, the
// centre fitted from the other views, its squared error on the view left out.
double CentreHeldOut(const ViewStats& stats, int kc, double eta) {
  double err = 0;
  for (int u = 0; u < int(stats.a.size()); ++u) {
    if (stats.s[u] == 0) continue;
    const Eigen::MatrixXd c = stats.Centre(kc, eta, u).topRows(kc);
    const Eigen::MatrixXd bu = stats.b[u].topRows(kc), au = stats.a[u].topLeftCorner(kc, kc);
    err += stats.s[u] - 2 * (c.array() * bu.array()).sum() + (c.array() * (au * c).array()).sum();
  }
  return err;
}

// The number of independent directions in a group's rows: the numerical rank of their normal
// matrix. Where every pixel sees the same directions (no field of view) it is the number of
// views; over any real field it is every component (the 21st eigenvalue is 1e-5 to 1e-4 of the
// largest at 0.1 degree on the card, 1e-16 at 0).
int RowRank(const Eigen::MatrixXd& normal_matrix) {
  const Eigen::VectorXd eigen =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(normal_matrix, Eigen::EigenvaluesOnly)
          .eigenvalues();
  const double tolerance = kRankTolerance * std::max(eigen.maxCoeff(), 0.0);
  return int((eigen.array() > tolerance).count());
}

// The most components a group's centre may take: a pixel's k, or more up to the rank of the
// group's rows. Past it a centre has seen no direction that a pixel has not: its extra
// components are placed by the ridge, not by the data, and its held-out views, taken from the
// same few directions, cannot tell how they extrapolate (the blend at 0 degrees, seeds 4 and 5:
// a group of 505 pixels took 64 components, its held-out views 1% better, the map 1.4% worse;
// docs/reconstruction.md).
int SupportedComponents(const ViewStats& stats, int k) {
  return std::max(k, RowRank(stats.a_all));
}

// The centre's components, k to `supported`, by its held-out error, the smallest within
// kSizeTolerance of the best.
int ChooseCentreComponents(const ViewStats& stats, int k, int supported, double eta) {
  const int K = int(stats.a_all.rows());
  std::vector<int> candidates;
  for (int kc = k; kc < K && kc <= supported; kc += 8) candidates.push_back(kc);
  if (K <= supported) candidates.push_back(K);
  int best_kc = k;
  double best = std::numeric_limits<double>::infinity();
  for (int kc : candidates) {
    const double err = CentreHeldOut(stats, kc, eta);
    if (err < best * (1 - kSizeTolerance)) best = err, best_kc = kc;
  }
  return best_kc;
}

// The centre's ridge (and its components at that ridge) by its held-out error, from eta times
// each fraction in turn: a smaller ridge is taken only if it lowers the error by
// kSizeTolerance (the smallest departure from the one-pixel regularisation that earns it).
void ChooseCentreRidge(const ViewStats& stats, int k, int supported, double eta,
                       const std::vector<double>& fractions, int* centre_components,
                       double* centre_eta) {
  std::vector<double> ridges = fractions;
  std::sort(ridges.begin(), ridges.end(), std::greater<double>());
  double best = std::numeric_limits<double>::infinity();
  for (double f : ridges) {
    const int kc = ChooseCentreComponents(stats, k, supported, eta * f);
    const double err = CentreHeldOut(stats, kc, eta * f);
    if (err < best * (1 - kSizeTolerance))
      best = err, *centre_components = kc, *centre_eta = eta * f;
  }
}

struct GroupFit {
  Eigen::MatrixXd centre;  // K x 3
  int centre_components = 0;
  double strength = 0, squared_error = 0;
  long observations = 0;
};

// The group's pixels' leave-one-view-out squared errors at each strength of the grid, summed over
// the pixels, each pixel's left-out view judged against centres[v] (K x 3, first kc used).
struct StrengthErrors {
  std::vector<double> sum;  // per strength
  long observations = 0;
};
StrengthErrors LeaveOneOutByStrength(const std::vector<SamplePixel>& pixels,
                                     const std::vector<int>& members,
                                     const std::vector<Eigen::MatrixXd>& centres, int kc,
                                     const std::vector<double>& grid) {
  // Each pixel's errors in its own slot, summed in order afterwards: the same model (and map)
  // whatever the threads' timing.
  std::vector<double> e(members.size() * grid.size());
#pragma omp parallel for schedule(dynamic, 16)
  for (std::size_t m = 0; m < members.size(); ++m)
    PooledLeaveOneOut(pixels[members[m]], centres, kc, grid, &e[m * grid.size()]);
  StrengthErrors out;
  out.sum.assign(grid.size(), 0);
  for (std::size_t m = 0; m < members.size(); ++m) {
    for (std::size_t s = 0; s < grid.size(); ++s) out.sum[s] += e[m * grid.size() + s];
    out.observations += long(pixels[members[m]].view.size());
  }
  return out;
}

// The group's error with the prior at its best strength, every view left out of the centre too
// (a centre cannot vouch for a view it saw): what the number of groups is chosen by.
double HeldOutAtBestStrength(const std::vector<SamplePixel>& pixels,
                             const std::vector<int>& members, const ViewStats& stats, int kc,
                             double eta, const std::vector<double>& grid) {
  const StrengthErrors held_out =
      LeaveOneOutByStrength(pixels, members, stats.CentresWithoutEachView(kc, eta), kc, grid);
  return *std::min_element(held_out.sum.begin(), held_out.sum.end());
}

// The strength with the least leave-one-view-out error over the group's pixels, each pixel's
// left-out view judged against the centre its solve will use (fit->centre, from every view), as
// the pooled solve judges whether a pixel takes the prior at all (pooled_solver.cpp). So the
// strength answers whether the pixels depart from their group where the group has looked, not
// how well a centre extrapolates to a view that none of them saw: judged the second way (the
// view left out of the centre too), the held-out views took weak priors on one material seen
// over a field (white paint alone through acqd: strength 20, 0.298 against 0.264 with the
// centre itself, its homogeneous error 0.265), because a pixel's own ridge extrapolates to a
// missing view more smoothly than a centre fitted without it; the map paid at the field's edges
// (docs/reconstruction.md, "The prior's strength judged against the centre the solve uses").
// Where pixels do differ (the marbled sample) both ways choose weak priors. The error reported
// (fit->squared_error) is still the honest held-out one, the view left out of the centre too, at
// the chosen strength.
void ChooseStrength(const std::vector<SamplePixel>& pixels, const std::vector<int>& members,
                    const ViewStats& stats, double eta, const std::vector<double>& grid,
                    GroupFit* fit) {
  const int kc = fit->centre_components;
  const StrengthErrors judged = LeaveOneOutByStrength(
      pixels, members, std::vector<Eigen::MatrixXd>(stats.a.size(), fit->centre), kc, grid);
  const std::size_t best =
      std::min_element(judged.sum.begin(), judged.sum.end()) - judged.sum.begin();
  const StrengthErrors held_out =
      LeaveOneOutByStrength(pixels, members, stats.CentresWithoutEachView(kc, eta), kc, grid);
  fit->strength = grid[best];
  fit->squared_error = held_out.sum[best];
  fit->observations = held_out.observations;
}

// The RMS misfit (log space) of a centre (K x 3) to each member's observations, in order.
std::vector<double> CentreMisfits(const std::vector<SamplePixel>& pixels,
                                  const std::vector<int>& members, const Eigen::MatrixXd& centre) {
  std::vector<double> misfit;
  for (int i : members) {
    const SamplePixel& p = pixels[i];
    const Eigen::MatrixXd r = p.y - p.rows.cast<double>() * centre;
    misfit.push_back(std::sqrt(r.squaredNorm() / (3.0 * double(p.view.size()))));
  }
  return misfit;
}

// The given percentile of the values (taken by copy: nth_element reorders them).
double PercentileOf(std::vector<double> values, double percentile) {
  const std::size_t at =
      std::min(values.size() - 1, std::size_t(percentile * double(values.size())));
  std::nth_element(values.begin(), values.begin() + at, values.end());
  return values[at];
}

// The given percentile over the members of the RMS misfit of the centre to each one's data.
double MisfitPercentile(const std::vector<SamplePixel>& pixels, const std::vector<int>& members,
                        const Eigen::MatrixXd& centre, double percentile) {
  return PercentileOf(CentreMisfits(pixels, members, centre), percentile);
}

// A group's centre is fitted again from the members its first fit explains best: this share of
// them. k-means groups hold mixed pixels and strays of other inks (on the colour card 190 brass
// pixels in pink jasper's group), and the design weighting puts the centre's weight at the
// sample's centre, where the card's inks meet. Through acqd on three colour cards, pink jasper
// 1.22 / 1.23x its homogeneous error -> 1.14 / 1.15x at 0.9 (1.11 / 1.16x at 0.75, the maps
// worse; 1.14 / 1.17x at 0.95); docs/reconstruction.md, "A centre from the members it explains".
constexpr double kCentreKeptShare = 0.9;
std::vector<int> MembersExplainedBest(const std::vector<SamplePixel>& pixels,
                                      const std::vector<int>& members,
                                      const Eigen::MatrixXd& centre) {
  if (int(members.size()) < 2 * kMinUsableSample) return members;  // too few to spare any
  const std::vector<double> misfit = CentreMisfits(pixels, members, centre);
  const double limit = PercentileOf(misfit, kCentreKeptShare);
  std::vector<int> kept;
  for (std::size_t m = 0; m < members.size(); ++m)
    if (misfit[m] <= limit) kept.push_back(members[m]);
  return kept;
}

double Rms(double squared, long observations) {
  return observations > 0 ? std::sqrt(squared / (3.0 * double(observations))) : 0.0;
}

// The group's centre and prior strength. Its centre is fitted again from the members its first
// fit explains best (kCentreKeptShare), unless the first centre, from every member, predicts the
// group's held-out views better by more than kSizeTolerance: the members left out were then part
// of the material, not strays. On the 50-ink sample the trimmed centres of the background ink's
// two groups had lost 22% and 40% of their design weight (the members left out lay where the
// plan's directions are) and predicted their held-out views 2% worse; that ink's error went from
// 0.228 to 0.909. On the colour cards every group's two centres are within 1% (pink jasper's
// strays left out as intended); docs/reconstruction.md, "Unless the members left out are the
// material".
// Adds the group's held-out squared error to *squared.
PooledGroup FitGroup(const std::vector<SamplePixel>& pixels, const std::vector<int>& members, int K,
                     int k, int views, double design_sigma, double eta,
                     const PooledOptions& options, const std::vector<double>& grid,
                     double* squared) {
  const ViewStats stats(pixels, members, K, views, design_sigma, options.leave_out_colour_fringes);
  GroupFit whole;
  double centre_eta = eta;
  const int supported = SupportedComponents(stats, k);
  whole.centre_components = ChooseCentreComponents(stats, k, supported, eta);
  if (!options.centre_eta_fractions.empty())
    ChooseCentreRidge(stats, k, supported, eta, options.centre_eta_fractions,
                      &whole.centre_components, &centre_eta);
  GroupFit trimmed = whole;
  whole.centre = stats.Centre(whole.centre_components, centre_eta);
  const std::vector<int> explained = MembersExplainedBest(pixels, members, whole.centre);
  const ViewStats kept(pixels, explained, K, views, design_sigma, options.leave_out_colour_fringes);
  trimmed.centre = kept.Centre(trimmed.centre_components, centre_eta);
  ChooseStrength(pixels, members, kept, eta, grid, &trimmed);
  bool from_every_member = false;
  if (explained.size() < members.size()) {
    ChooseStrength(pixels, members, stats, eta, grid, &whole);
    from_every_member = Rms(whole.squared_error, whole.observations) <
                        Rms(trimmed.squared_error, trimmed.observations) * (1 - kSizeTolerance);
  }
  const GroupFit& fit = from_every_member ? whole : trimmed;
  PooledGroup group;
  group.centre.resize(3 * K);
  for (int ch = 0; ch < 3; ++ch)
    for (int j = 0; j < K; ++j) group.centre[ch * K + j] = float(fit.centre(j, ch));
  group.centre_components = fit.centre_components;
  group.centre_eta = centre_eta;
  group.strength = fit.strength;
  group.sample_pixels = int(members.size());
  group.centre_members = from_every_member ? int(members.size()) : int(explained.size());
  group.effective_pixels = (from_every_member ? stats : kept).effective_pixels;
  group.colour_outliers = stats.left_out;  // found over all its members
  group.held_out_rms = Rms(fit.squared_error, fit.observations);
  group.misfit_limit = MisfitPercentile(pixels, members, fit.centre, 0.99);
  *squared += fit.squared_error;
  return group;
}

}  // namespace

PooledModel FitPooledModel(const BasisView& basis, const PixelObservations& sample,
                           const PixelSolveOptions& solve, const PooledOptions& options) {
  solve.Check(basis);
  options.Check();
  const int k = solve.components;
  const int K = basis.components;  // k_c is chosen up to every component the basis stores
  PooledModel model;
  model.components = K;
  model.design_sigma_deg = options.design_sigma_deg;
  model.features = std::min(k, kFeatureComponents);
  std::size_t valid_bins = 0;
  for (std::size_t b = 0; b < merl::kBins; ++b) valid_bins += basis.valid[b] != 0;
  for (int i = 0; i < K; ++i)
    model.weight.push_back(basis.singular_values[i] /
                           std::sqrt(double(std::max<std::size_t>(valid_bins, 1))));

  const std::vector<SamplePixel> pixels = PrepareSample(basis, sample, solve, K, model);
  model.sample_pixels = int(pixels.size());
  double independent = 0;
  long observations = 0;
  for (const SamplePixel& p : pixels)
    independent += p.independent_sq, observations += long(p.view.size());
  model.independent_held_out_rms = model.held_out_rms = Rms(independent, observations);
  if (int(pixels.size()) < kMinUsableSample) return model;

  const std::vector<double> grid = StrengthGrid(solve.eta);
  const double design_sigma = DegToRad(options.design_sigma_deg);
  auto members_of = [&](const std::vector<int>& label, int groups) {
    std::vector<std::vector<int>> members(groups);
    for (int i = 0; i < int(label.size()); ++i) members[label[i]].push_back(i);
    return members;
  };
  // G by held-out views, with every centre at k components (its own size is chosen next).
  std::vector<int> tried;
  if (options.groups > 0) {
    tried = {std::min(options.groups, int(pixels.size()))};
  } else {
    for (int g : {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256})
      if (g <= options.max_groups && g * 8 <= int(pixels.size())) tried.push_back(g);
  }
  // The merge's inputs, only when it runs (a forced number of groups is kept as k-means cut it).
  const bool merge = options.groups <= 0;
  Eigen::MatrixXd feature_matrix(merge ? pixels.size() : 0, 3 * model.features);
  Eigen::MatrixX2d field_matrix = Eigen::MatrixX2d::Zero(feature_matrix.rows(), 2);
  for (Eigen::Index i = 0; i < feature_matrix.rows(); ++i) {
    feature_matrix.row(i) = Eigen::Map<const Eigen::RowVectorXd>(
        pixels[std::size_t(i)].feature.data(), feature_matrix.cols());
    if (options.merge_in_field) field_matrix.row(i) = pixels[std::size_t(i)].field.transpose();
  }
  std::vector<int> label;  // the best labelling so far, of `groups` groups
  std::vector<int> previous_trial;
  int groups = 0, previous = 0, worse_in_a_row = 0;
  double best = std::numeric_limits<double>::infinity();
  for (int seeded : tried) {
    std::vector<int> trial = KMeans(pixels, seeded, options.seed);
    const int size =
        merge ? MergeOverlapping(feature_matrix, field_matrix, seeded, &trial) : seeded;
    double squared = 0;
    for (const std::vector<int>& members : members_of(trial, size)) {
      if (members.empty()) continue;
      const ViewStats stats(pixels, members, k, sample.views, design_sigma,
                            options.leave_out_colour_fringes);
      squared += HeldOutAtBestStrength(pixels, members, stats, k, solve.eta, grid);
    }
    const double rms = Rms(squared, observations);
    model.selection.push_back({size, rms});
    // A trial that merged back to a size already tried is not taken. It ends the search, as a
    // larger size that did not earn its keep does, three in a row, only if its groups are the
    // previous trial's: k-means found nothing new. Groups merged back but cut differently mean
    // k-means is still spending its seeds on one widely scattered material (a mirror-like ink
    // over relief: seeded 3, 4 and 6 each merged back to 2, differently; at 8 the small inks
    // got groups of their own and the map went from 0.707 to 0.319).
    const bool repeat = previous > 0 && size <= previous;
    const bool counts_towards_end = !repeat || SameGrouping(trial, previous_trial);
    previous = size;
    previous_trial = trial;
    if (!repeat && rms < best * (1 - kGroupTolerance)) {
      best = rms, label = std::move(trial), groups = size, worse_in_a_row = 0;
    } else if (counts_towards_end && ++worse_in_a_row == 3) {
      break;
    }
  }
  const std::vector<std::vector<int>> members = members_of(label, groups);
  const std::vector<std::vector<double>> features = GroupMeans(pixels, label, groups);
  double squared = 0;
  for (int g = 0; g < groups; ++g) {
    if (members[g].empty()) continue;
    PooledGroup group = FitGroup(pixels, members[g], K, k, sample.views, design_sigma, solve.eta,
                                 options, grid, &squared);
    group.feature = features[g];
    model.groups.push_back(std::move(group));
  }
  model.held_out_rms = Rms(squared, observations);
  // The groups must earn their keep against none at all (every pixel alone), as a larger model
  // must against a smaller one: where the near field leaves the pixels nothing to share (a field
  // of view of 0 on a smooth blend), a gain under kSizeTolerance is the noise of the groups' and
  // the priors' choice (docs/reconstruction.md, "No groups unless they earn their keep"). A
  // number of groups the user forced is kept.
  if (options.groups <= 0 && options.groups_must_beat_independent &&
      model.held_out_rms > model.independent_held_out_rms * (1 - kSizeTolerance)) {
    model.groups.clear();
    model.dropped_held_out_rms = model.held_out_rms;
    model.held_out_rms = model.independent_held_out_rms;
  }
  return model;
}

}  // namespace acq
