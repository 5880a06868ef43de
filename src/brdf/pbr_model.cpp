// GCC 12 with AVX-512 (-march=native) warns 50 times in this file that Eigen's matrix-vector
// kernel may read an uninitialised register (avx512fintrin.h's '__Y'): a false positive inside
// its own intrinsics, instantiated here by the fit's fixed-size matrices. Silenced for this file
// only, before its first include (which brings in Eigen), so that a real warning stands out.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "brdf/pbr_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "brdf/log_mapping.h"
#include "core/error.h"
#include "core/merl_grid.h"

namespace acq {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The specular lobe without Fresnel, D G / (4 cos_i cos_o), at alpha.
double Lobe(double alpha, double cos_in, double cos_out, double cos_h) {
  const double a2 = alpha * alpha;
  const double t = cos_h * cos_h * (a2 - 1) + 1;
  const double d = a2 / (kPi * t * t);
  auto g1 = [a2](double c) { return 2 * c / (c + std::sqrt(a2 + (1 - a2) * c * c)); };
  return d * g1(cos_in) * g1(cos_out) / (4 * cos_in * cos_out);
}

double SchlickWeight(double cos_d) {
  const double m = std::clamp(1 - cos_d, 0.0, 1.0);
  return m * m * m * m * m;
}

// The grid's theta_h indices: every 4th bin, as dense as MERL's own grid (sqrt-spaced in angle),
// so that the fit weights the peak and the shoulder as the method's error over all bins does.
// Until 2026-12-03 it took every bin near the peak (7 of 21 values within half a degree, 4x
// MERL's share): white paint's fit then went for its sharp peak and missed its broad shoulder
// (validation views near the highlight 1.90x and 3.63x the measured map's; now 1.70x and 2.96x,
// docs/export.md).
constexpr int kThetaH[] = {0,  4,  8,  12, 16, 20, 24, 28, 32, 36, 40, 44,
                           48, 52, 56, 60, 64, 68, 72, 76, 80, 84, 88};
constexpr int kThetaDStep = 8, kPhiDStep = 30;  // 11 theta_d and 6 phi_d bin centres

// The coarse search's solve for one channel at a fixed lobe: minimise sum W (a b1 + b b2 + b3 -
// t)^2 over a >= 0, 0 <= b <= 1, given the sums A (2 x 2), r = sum W b (t - b3), and c = sum W
// (t - b3)^2. The minimum lies inside or on an edge; each candidate's error is exact.
struct ChannelSolve {
  double a = 0, b = 0, error = 0;
};

ChannelSolve SolveBounded(const Eigen::Matrix2d& A, const Eigen::Vector2d& r, double c) {
  auto error = [&](double a, double b) {
    const Eigen::Vector2d x(a, b);
    return c - 2 * x.dot(r) + x.dot(A * x);
  };
  ChannelSolve best{0, 0, error(0, 0)};
  auto consider = [&](double a, double b) {
    if (!(a >= 0 && b >= 0 && b <= 1)) return;
    const double e = error(a, b);
    if (e < best.error) best = {a, b, e};
  };
  const double det = A.determinant();
  if (std::abs(det) > 1e-300)
    consider((r(0) * A(1, 1) - r(1) * A(0, 1)) / det, (r(1) * A(0, 0) - r(0) * A(0, 1)) / det);
  if (A(0, 0) > 0) {
    consider(std::max(r(0) / A(0, 0), 0.0), 0);              // b = 0
    consider(std::max((r(0) - A(0, 1)) / A(0, 0), 0.0), 1);  // b = 1
  }
  if (A(1, 1) > 0) consider(0, std::clamp(r(1) / A(1, 1), 0.0, 1.0));  // a = 0
  consider(0, 1);
  return best;
}

// The fit's data: the bins with a finite target, their geometry, the targets (clamped to >= 0)
// and their log-mapped values ln(t cosw + eps), as arrays over the used bins.
struct FitData {
  Eigen::ArrayXd cos_in, cos_out, cos_h, schlick, cos_weight;
  std::array<Eigen::ArrayXd, 3> t, lt;
  Eigen::Index Size() const { return cos_in.size(); }
};

FitData Prepare(const PbrFitGrid& grid, const float* target) {
  std::vector<int> used;
  for (std::size_t n = 0; n < grid.Size(); ++n) {
    const float* v = target + 3 * n;
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) used.push_back(int(n));
  }
  FitData d;
  const Eigen::Index n = Eigen::Index(used.size());
  for (auto* a : {&d.cos_in, &d.cos_out, &d.cos_h, &d.schlick, &d.cos_weight}) a->resize(n);
  for (int c = 0; c < 3; ++c) d.t[c].resize(n), d.lt[c].resize(n);
  for (Eigen::Index u = 0; u < n; ++u) {
    const int b = used[std::size_t(u)];
    d.cos_in(u) = grid.cos_in[b];
    d.cos_out(u) = grid.cos_out[b];
    d.cos_h(u) = grid.cos_h[b];
    d.schlick(u) = SchlickWeight(grid.cos_d[b]);
    d.cos_weight(u) = grid.cos_weight[b];
    for (int c = 0; c < 3; ++c) d.t[c](u) = std::max(double(target[3 * b + c]), 0.0);
  }
  for (int c = 0; c < 3; ++c) d.lt[c] = (d.t[c] * d.cos_weight + kLogMappingEps).log();
  return d;
}

// The lobe D G / (4 cos_i cos_o) over the used bins at alpha.
Eigen::ArrayXd LobeOver(const FitData& d, double alpha) {
  const double a2 = alpha * alpha;
  const Eigen::ArrayXd t = d.cos_h.square() * (a2 - 1) + 1;
  auto g1 = [a2](const Eigen::ArrayXd& c) {
    return 2 * c / (c + (a2 + (1 - a2) * c.square()).sqrt());
  };
  return a2 / (kPi * t.square()) * g1(d.cos_in) * g1(d.cos_out) / (4 * d.cos_in * d.cos_out);
}

double RoughnessAt(int j, int steps) {
  const double f = steps > 1 ? double(j) / (steps - 1) : 0.5;
  return kPbrMinRoughness * std::pow(kPbrMaxRoughness / kPbrMinRoughness, f);
}

// The specular weights the coarse search tries: 1 (Schlick's Fresnel to 1 at grazing) and two
// lower (measured materials that do not rise as far: white paint fits at 0.29).
constexpr double kCoarseSpecular[] = {1.0, 0.3, 0.1};

// The coarse search: per specular weight and roughness, the weighted linear fit of diffuse and
// F0 per channel in the linearised log error (weights cosw / (t cosw + eps), squared), the best
// solution.
PbrParameters CoarseSearch(const FitData& d, int steps, PbrModel model) {
  std::array<Eigen::ArrayXd, 3> W;
  for (int c = 0; c < 3; ++c)
    W[c] = (d.cos_weight / (d.t[c] * d.cos_weight + kLogMappingEps)).square();
  PbrParameters best;
  double best_error = INFINITY;
  for (int j = 0; j < steps; ++j) {
    const double roughness = RoughnessAt(j, steps);
    const Eigen::ArrayXd lobe = LobeOver(d, roughness * roughness);
    for (const double specular : kCoarseSpecular) {
      if (model == PbrModel::kSchlick && specular != 1.0) continue;
      const Eigen::ArrayXd b2 = specular * lobe * (1 - d.schlick), b3 = specular * lobe * d.schlick;
      PbrParameters p;
      p.roughness = roughness;
      p.specular = specular;
      double error = 0;
      for (int c = 0; c < 3; ++c) {
        const Eigen::ArrayXd dt = d.t[c] - b3, wb2 = W[c] * b2;
        Eigen::Matrix2d A;
        A(0, 0) = W[c].sum() / (kPi * kPi);
        A(0, 1) = A(1, 0) = wb2.sum() / kPi;
        A(1, 1) = (wb2 * b2).sum();
        const Eigen::Vector2d r((W[c] * dt).sum() / kPi, (wb2 * dt).sum());
        const ChannelSolve s = SolveBounded(A, r, (W[c] * dt.square()).sum());
        p.diffuse[c] = s.a;
        p.f0[c] = s.b;
        error += s.error;
      }
      if (error < best_error) best_error = error, best = p;
    }
  }
  return best;
}

// The parameters as one vector: diffuse R G B, F0 R G B, ln roughness, specular weight, coat
// weight, ln coat roughness. Without a coat the last two are held at 0 and ln 0.1.
constexpr int kParameters = 10;
constexpr int kRoughnessAt = 6;
constexpr int kSpecularAt = 7;
constexpr int kCoatAt = 8;  // the first of the coat's two
using Theta = Eigen::Matrix<double, kParameters, 1>;
using Normal = Eigen::Matrix<double, kParameters, kParameters>;

Theta Pack(const PbrParameters& p) {
  Theta t;
  for (int c = 0; c < 3; ++c) t(c) = p.diffuse[c], t(3 + c) = p.f0[c];
  t(kRoughnessAt) = std::log(p.roughness);
  t(kSpecularAt) = p.specular;
  t(kCoatAt) = p.coat;
  t(kCoatAt + 1) = std::log(p.coat_roughness);
  return t;
}

PbrParameters Unpack(const Theta& t) {
  PbrParameters p;
  for (int c = 0; c < 3; ++c) p.diffuse[c] = t(c), p.f0[c] = t(3 + c);
  p.roughness = std::exp(t(kRoughnessAt));
  p.specular = t(kSpecularAt);
  p.coat = t(kCoatAt);
  p.coat_roughness = std::exp(t(kCoatAt + 1));
  return p;
}

struct Bounds {
  Theta lo, hi;
};

Bounds ParameterBounds() {
  Bounds b;
  for (int c = 0; c < 3; ++c) b.lo(c) = 0, b.hi(c) = INFINITY, b.lo(3 + c) = 0, b.hi(3 + c) = 1;
  b.lo(kRoughnessAt) = b.lo(kCoatAt + 1) = std::log(kPbrMinRoughness);
  b.hi(kRoughnessAt) = b.hi(kCoatAt + 1) = std::log(kPbrMaxRoughness);
  b.lo(kSpecularAt) = b.lo(kCoatAt) = 0, b.hi(kSpecularAt) = b.hi(kCoatAt) = 1;
  return b;
}

void Project(Theta* t) {
  static const Bounds b = ParameterBounds();
  *t = t->cwiseMax(b.lo).cwiseMin(b.hi);
}

// A parameter on a bound that the gradient pushes outwards is held there (its row and column
// taken out of the step): projecting a step that crosses it instead only creeps along the bound
// (measured: 40-120 iterations for a rough fabric at roughness 1, 5-20 with the bound held).
// The parameters a model leaves out (`fixed`) are held always.
using Fixed = std::array<bool, kParameters>;

Fixed FixedBy(PbrModel model, bool coat) {
  Fixed fixed{};
  fixed[kSpecularAt] = model == PbrModel::kSchlick;
  fixed[kCoatAt] = fixed[kCoatAt + 1] = !coat;
  return fixed;
}

void HoldParameters(const Theta& theta, const Fixed& fixed, Normal* a, Theta* g) {
  static const Bounds b = ParameterBounds();
  for (int i = 0; i < kParameters; ++i) {
    // The step is -a^-1 g: a positive gradient moves the parameter down.
    const bool held = fixed[std::size_t(i)] || (theta(i) <= b.lo(i) && (*g)(i) > 0) ||
                      (theta(i) >= b.hi(i) && (*g)(i) < 0);
    if (!held) continue;
    a->row(i).setZero();
    a->col(i).setZero();
    (*a)(i, i) = 1;
    (*g)(i) = 0;
  }
}

// A lobe over the used bins and its derivative in ln roughness.
struct LobeAndSlope {
  Eigen::ArrayXd value, slope;
};

LobeAndSlope LobeWithSlope(const FitData& d, double ln_roughness) {
  // alpha^2 = roughness^4, so d/d(ln roughness) = 4 alpha^2 d/d(alpha^2); the lobe's logarithmic
  // derivative is the sum of D's and the two G1's.
  const double a2 = std::exp(4 * ln_roughness);
  const Eigen::ArrayXd c2 = d.cos_h.square();
  const Eigen::ArrayXd t = c2 * (a2 - 1) + 1;
  const Eigen::ArrayXd dlog_d = 1 / a2 - 2 * c2 / t;
  auto g1 = [a2](const Eigen::ArrayXd& c, Eigen::ArrayXd* dlog) -> Eigen::ArrayXd {
    const Eigen::ArrayXd root = (a2 + (1 - a2) * c.square()).sqrt();
    *dlog = -(1 - c.square()) / (2 * root * (c + root));
    return 2 * c / (c + root);
  };
  Eigen::ArrayXd dlog_in, dlog_out;
  const Eigen::ArrayXd g = g1(d.cos_in, &dlog_in) * g1(d.cos_out, &dlog_out);
  LobeAndSlope l;
  l.value = a2 / (kPi * t.square()) * g / (4 * d.cos_in * d.cos_out);
  l.slope = l.value * (4 * a2) * (dlog_d + dlog_in + dlog_out);
  return l;
}

// The log-space cost and the Gauss-Newton system J^T J, J^T r. Each residual depends on its
// channel's diffuse and F0, the roughness, the specular weight and the coat's two, and through
// the diffuse's share (1 - F90 F at the largest F0) on the largest F0: up to seven columns.
double Cost(const FitData& d, const Theta& theta, bool coat, Normal* jtj, Theta* jtr) {
  const LobeAndSlope base = LobeWithSlope(d, theta(kRoughnessAt));
  const LobeAndSlope top = coat ? LobeWithSlope(d, theta(kCoatAt + 1)) : LobeAndSlope{};
  const double specular = theta(kSpecularAt), w = coat ? theta(kCoatAt) : 0.0;
  const Eigen::ArrayXd coat_fresnel = kPbrCoatF0 + (1 - kPbrCoatF0) * d.schlick;
  const Eigen::ArrayXd under = 1 - w * coat_fresnel;  // what the coat lets through
  int top_f0 = 0;                                     // the channel whose F0 is largest
  for (int c = 1; c < 3; ++c)
    if (theta(3 + c) > theta(3 + top_f0)) top_f0 = c;
  const Eigen::ArrayXd top_fresnel = theta(3 + top_f0) * (1 - d.schlick) + d.schlick;
  const Eigen::ArrayXd diffuse_share = 1 - specular * top_fresnel;
  jtj->setZero();
  jtr->setZero();
  double cost = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::ArrayXd fresnel = theta(3 + c) * (1 - d.schlick) + d.schlick;
    const Eigen::ArrayXd lobe = specular * base.value * fresnel;
    const Eigen::ArrayXd uncoated = theta(c) / kPi * diffuse_share + lobe;
    Eigen::ArrayXd f = under * uncoated;
    if (coat) f += w * coat_fresnel * top.value;
    const Eigen::ArrayXd mapped = f * d.cos_weight + kLogMappingEps;
    const Eigen::ArrayXd res = mapped.log() - d.lt[c];
    cost += res.square().sum();
    const Eigen::ArrayXd g = d.cos_weight / mapped, gu = g * under;
    // The diffuse's share falls with the largest F0: d/dF0_top of (rho / pi) share.
    const Eigen::ArrayXd through_top = -gu * theta(c) / kPi * specular * (1 - d.schlick);
    std::vector<std::pair<int, Eigen::ArrayXd>> j = {
        {c, gu * diffuse_share / kPi},
        {3 + c, gu * specular * base.value * (1 - d.schlick)},
        {kRoughnessAt, gu * specular * fresnel * base.slope},
        {kSpecularAt, gu * (base.value * fresnel - theta(c) / kPi * top_fresnel)}};
    if (c == top_f0)
      j[1].second += through_top;
    else
      j.emplace_back(3 + top_f0, through_top);
    if (coat) {
      j.emplace_back(kCoatAt, g * coat_fresnel * (top.value - uncoated));
      j.emplace_back(kCoatAt + 1, g * w * coat_fresnel * top.slope);
    }
    for (std::size_t a = 0; a < j.size(); ++a) {
      (*jtr)(j[a].first) += (j[a].second * res).sum();
      for (std::size_t b = a; b < j.size(); ++b) {
        const double v = (j[a].second * j[b].second).sum();
        (*jtj)(j[a].first, j[b].first) += v;
        if (b != a) (*jtj)(j[b].first, j[a].first) += v;
      }
    }
  }
  return cost;
}

struct Refined {
  Theta theta;
  double cost = INFINITY;
  bool converged = false;
  int iterations = 0;
};

// Levenberg-Marquardt with Marquardt's diagonal scaling, each step projected onto the bounds.
// Converged: an accepted step that lowers the cost by less than a part in 1e4 (the RMS by 5e-5
// of itself), or a point no step can improve (the damping grows past any useful size: a
// minimum, possibly on a bound).
Refined Refine(const FitData& data, Theta theta, const Fixed& fixed, int max_iterations) {
  const bool coat = !fixed[kCoatAt];
  Normal jtj, next_jtj;
  Theta jtr, next_jtr;
  Refined r;
  double cost = Cost(data, theta, coat, &jtj, &jtr);
  double lambda = 1e-3;
  for (r.iterations = 1; r.iterations <= max_iterations; ++r.iterations) {
    Normal a = jtj;
    a.diagonal() += lambda * (jtj.diagonal().array() + 1e-12).matrix();
    Theta g = jtr;
    HoldParameters(theta, fixed, &a, &g);
    Theta next = theta - a.ldlt().solve(g);
    Project(&next);
    const double next_cost = Cost(data, next, coat, &next_jtj, &next_jtr);
    if (std::isfinite(next_cost) && next_cost < cost) {
      const bool small = cost - next_cost < 1e-4 * cost;
      theta = next;
      cost = next_cost;
      jtj = next_jtj;
      jtr = next_jtr;
      lambda = std::max(lambda / 3, 1e-9);
      if (small) {
        r.converged = true;
        break;
      }
    } else {
      lambda *= 4;
      if (lambda > 1e8) {
        r.converged = true;
        break;
      }
    }
  }
  r.iterations = std::min(r.iterations, max_iterations);
  r.theta = theta;
  r.cost = cost;
  return r;
}

// The coat's starting points from the uncoated fit, at half weight: the coat sharper than the
// lobe by 2x in roughness and the lobe broader by 1.5x, the coat 4x sharper, and the coat 2x
// broader (white paint's optimum: a sharp lobe and a dim broad coat). The first alone missed
// white paint's; on the three pixels checked against SciPy's least_squares from 15 starts, these
// three found the same optimum (docs/export.md).
std::vector<Theta> CoatStarts(const Theta& uncoated) {
  std::vector<Theta> starts;
  for (const auto& [sharper, broader] :
       {std::pair{2.0, 1.5}, std::pair{4.0, 1.0}, std::pair{0.5, 1.0}}) {
    Theta t = uncoated;
    t(kRoughnessAt) += std::log(broader);
    t(kCoatAt) = 0.5;
    t(kCoatAt + 1) = uncoated(kRoughnessAt) - std::log(sharper);
    Project(&t);
    starts.push_back(t);
  }
  return starts;
}

// A lobe of weight 0 leaves its shape to the optimiser's last step, and a renderer that blends
// neighbouring texels (MaterialX's GLSL renderer does, whatever the filter asked) then gives the
// blend that shape with half the neighbour's weight: a lobe neither texel has. So an unused lobe
// takes the other lobe's roughness (and an unused F0 glTF's default, 0.04), and a blend changes a
// lobe's weight, not its shape. Measured on the colour card's black fabric, whose pixels fall in
// two optima (a dark diffuse under a broad coat, a brighter one under a broad lobe): MaterialX's
// render of the fabric spread 0.35 relative (0.03 measured) before this, 0.05 after.
// A weight under half an 8-bit texture step is written as 0, so it counts as unused here.
void GiveUnusedParametersTheirCounterparts(PbrParameters* p) {
  constexpr double kUnused = 0.5 / 255;
  if (p->coat < kUnused) p->coat = 0;
  if (p->specular < kUnused) p->specular = 0;
  if (p->coat == 0) p->coat_roughness = p->roughness;
  if (p->specular == 0) {
    if (p->coat > 0) p->roughness = p->coat_roughness;
    p->f0 = {kPbrCoatF0, kPbrCoatF0, kPbrCoatF0};
  }
}

}  // namespace

std::array<double, 3> EvaluatePbr(const PbrParameters& p, const Eigen::Vector3d& in,
                                  const Eigen::Vector3d& out) {
  if (!(in.z() > 0 && out.z() > 0)) return {0, 0, 0};
  const Eigen::Vector3d h = (in + out).normalized();
  const double lobe = Lobe(p.roughness * p.roughness, in.z(), out.z(), h.z());
  const double s = SchlickWeight(in.dot(h));
  const double coat_fresnel = p.coat * (kPbrCoatF0 + (1 - kPbrCoatF0) * s);
  const double coat =
      p.coat > 0 ? coat_fresnel * Lobe(p.coat_roughness * p.coat_roughness, in.z(), out.z(), h.z())
                 : 0.0;
  const double top_f0 = std::max({p.f0[0], p.f0[1], p.f0[2]});
  const double diffuse_share = 1 - p.specular * (top_f0 * (1 - s) + s);
  std::array<double, 3> f;
  for (int c = 0; c < 3; ++c)
    f[c] = (1 - coat_fresnel) *
               (p.diffuse[c] / kPi * diffuse_share + p.specular * lobe * (p.f0[c] * (1 - s) + s)) +
           coat;
  return f;
}

PbrFitGrid PbrFitGrid::Default(const std::uint8_t* valid, double max_zenith) {
  PbrFitGrid g;
  const double min_cos = std::cos(max_zenith);
  for (int h : kThetaH)
    for (int d = kThetaDStep / 2; d < merl::kThetaD; d += kThetaDStep)
      for (int p = kPhiDStep / 2; p < merl::kPhiD; p += kPhiDStep) {
        const merl::BinIndex b{h, d, p};
        const std::size_t flat = b.Flat();
        if (!valid[flat]) continue;
        const DirectionPair dir = DirectionsFromRusinkiewicz(merl::BinCentre(b));
        if (dir.in.z() < min_cos || dir.out.z() < min_cos) continue;
        const Eigen::Vector3d half = (dir.in + dir.out).normalized();
        g.bins.push_back(std::uint32_t(flat));
        g.cos_in.push_back(dir.in.z());
        g.cos_out.push_back(dir.out.z());
        g.cos_h.push_back(half.z());
        g.cos_d.push_back(dir.in.dot(half));
        g.cos_weight.push_back(merl::CosWeight(dir));
      }
  return g;  // ascending: theta_h, then theta_d, then phi_d is the flat index's order
}

namespace {
constexpr std::pair<PbrModel, const char*> kPbrModelNames[] = {{PbrModel::kSchlick, "schlick"},
                                                               {PbrModel::kWeighted, "weighted"},
                                                               {PbrModel::kCoated, "coated"}};
}  // namespace

const char* PbrModelName(PbrModel model) {
  for (const auto& [m, name] : kPbrModelNames)
    if (m == model) return name;
  throw std::logic_error("PbrModel missing from kPbrModelNames");
}

PbrModel ParsePbrModel(const std::string& name, const std::string& where) {
  for (const auto& [m, n] : kPbrModelNames)
    if (name == n) return m;
  throw UserError(where, "unknown model '" + name + "'",
                  "use schlick (Lambert + GGX), weighted (+ the lobe's weight, F90) or coated "
                  "(+ a coat where a pixel needs one; the default)");
}

void PbrFitOptions::Check() const {
  if (!(max_zenith_deg >= 30 && max_zenith_deg <= 90))
    throw UserError("--max-zenith-deg",
                    "must be between 30 and 90 degrees, got " + std::to_string(max_zenith_deg),
                    "the default is 70");
  if (roughness_steps < 2 || roughness_steps > 256)
    throw UserError("--roughness-steps",
                    "must be between 2 and 256, got " + std::to_string(roughness_steps),
                    "the default is 16");
  if (max_iterations < 1 || max_iterations > 1000)
    throw UserError("--max-iterations",
                    "must be between 1 and 1000, got " + std::to_string(max_iterations),
                    "the default is 100");
}

PbrFit FitPbr(const PbrFitGrid& grid, const float* target, const PbrFitOptions& options) {
  PbrFit fit;
  const FitData data = Prepare(grid, target);
  if (data.Size() == 0) return fit;
  const double count = 3.0 * double(data.Size());
  Refined best = Refine(data, Pack(CoarseSearch(data, options.roughness_steps, options.model)),
                        FixedBy(options.model, false), options.max_iterations);
  fit.uncoated_log_rmse = std::sqrt(best.cost / count);
  if (options.model == PbrModel::kCoated) {
    const double needed = best.cost * (1 - kPbrCoatMinGain) * (1 - kPbrCoatMinGain);
    for (const Theta& start : CoatStarts(best.theta)) {
      const Refined coated =
          Refine(data, start, FixedBy(options.model, true), options.max_iterations);
      if (coated.cost < needed && coated.cost < best.cost) best = coated;
    }
  }
  fit.parameters = Unpack(best.theta);
  GiveUnusedParametersTheirCounterparts(&fit.parameters);
  fit.iterations = best.iterations;
  fit.converged = best.converged;
  fit.log_rmse = std::sqrt(best.cost / count);
  if (!std::isfinite(fit.log_rmse)) fit.log_rmse = fit.uncoated_log_rmse = 0, fit.converged = false;
  return fit;
}

}  // namespace acq
