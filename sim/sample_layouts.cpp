#include "sim/sample_layouts.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "core/error.h"
#include "io/float_planes_exr.h"
#include "sim/sample_files.h"

namespace acq::sim {
namespace {

constexpr int kWeightSteps = 16;  // mixture weights are multiples of 1/16

// Collects distinct quantised mixtures as labels.
class MixtureTable {
 public:
  explicit MixtureTable(std::string where) : where_(std::move(where)) {}
  // The label of the mixture (weights quantised to 1/16, renormalised).
  std::uint8_t Label(Mixture m) {
    int total = 0;
    std::vector<std::pair<int, int>> steps;
    for (const auto& [material, w] : m) {
      const int s = int(std::lround(w * kWeightSteps));
      if (s > 0) steps.push_back({material, s}), total += s;
    }
    if (steps.empty()) steps.push_back({m.front().first, kWeightSteps}), total = kWeightSteps;
    // Rounding can miss one by a step: the largest part takes the difference.
    auto largest = std::max_element(steps.begin(), steps.end(),
                                    [](auto& a, auto& b) { return a.second < b.second; });
    largest->second += kWeightSteps - total;
    std::sort(steps.begin(), steps.end());
    const auto found = labels_.find(steps);
    if (found != labels_.end()) return found->second;
    if (labels_.size() == 255)
      throw UserError(where_, "more than 255 distinct mixtures (at 1/16 steps of weight)",
                      "use fewer materials or smoother weights");
    const std::uint8_t label = std::uint8_t(labels_.size());
    labels_[steps] = label;
    Mixture q;
    for (const auto& [material, s] : steps) q.push_back({material, double(s) / kWeightSteps});
    mixtures_.push_back(q);
    return label;
  }
  std::vector<Mixture> Take() { return std::move(mixtures_); }

 private:
  std::string where_;
  std::map<std::vector<std::pair<int, int>>, std::uint8_t> labels_;
  std::vector<Mixture> mixtures_;
};

SyntheticSvbrdf EmptyLayout(int width, int height, double size_mm) {
  SyntheticSvbrdf s;
  s.width = width;
  s.height = height;
  s.sample_size_mm = size_mm;
  s.label.assign(std::size_t(width) * height, 0);
  return s;
}

// Smooth value noise in [0, 1]: octaves of bilinearly interpolated random lattices.
class ValueNoise {
 public:
  explicit ValueNoise(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    for (double& v : lattice_) v = u(rng);
  }
  double At(double x, double y) const {
    double sum = 0, amplitude = 0.5, norm = 0;
    for (int octave = 0; octave < 4; ++octave, x *= 2, y *= 2, amplitude /= 2) {
      const double fx = x - std::floor(x), fy = y - std::floor(y);
      const int ix = int(std::floor(x)), iy = int(std::floor(y));
      auto v = [&](int a, int b) {
        return lattice_[((a & 63) * 64 + (b & 63) + octave * 17) % 4096];
      };
      const double sx = fx * fx * (3 - 2 * fx), sy = fy * fy * (3 - 2 * fy);
      sum += amplitude * ((v(ix, iy) * (1 - sx) + v(ix + 1, iy) * sx) * (1 - sy) +
                          (v(ix, iy + 1) * (1 - sx) + v(ix + 1, iy + 1) * sx) * sy);
      norm += amplitude;
    }
    return sum / norm;
  }

 private:
  std::array<double, 4096> lattice_{};
};

// Lines of "letters" of material 1 on material 0: vertical strokes 2-3 pixels wide and
// horizontal bars 2-3 pixels high, the scale of small print seen by the reference camera.
void DrawText(SyntheticSvbrdf* s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> thickness(2, 3), shape(0, 3);
  auto fill = [s](int x0, int y0, int x1, int y1) {
    for (int y = std::max(y0, 0); y < std::min(y1, s->height); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, s->width); ++x)
        s->label[std::size_t(y) * s->width + x] = 1;
  };
  const int line_height = 16;
  for (int y0 = 4; y0 + line_height <= s->height; y0 += line_height + 6)
    for (int x0 = 4; x0 + 10 <= s->width; x0 += 12) {
      const int t = thickness(rng);
      switch (shape(rng)) {
        case 0:  // I
          fill(x0 + 4, y0, x0 + 4 + t, y0 + line_height);
          break;
        case 1:  // L
          fill(x0, y0, x0 + t, y0 + line_height);
          fill(x0, y0 + line_height - t, x0 + 9, y0 + line_height);
          break;
        case 2:  // T
          fill(x0, y0, x0 + 9, y0 + t);
          fill(x0 + 4, y0, x0 + 4 + t, y0 + line_height);
          break;
        default:  // H
          fill(x0, y0, x0 + t, y0 + line_height);
          fill(x0 + 9 - t, y0, x0 + 9, y0 + line_height);
          fill(x0, y0 + line_height / 2 - 1, x0 + 9, y0 + line_height / 2 - 1 + t);
      }
    }
}

}  // namespace

std::vector<std::string> MixedSample::Names(const std::vector<std::string>& materials) const {
  std::vector<std::string> names;
  for (const Mixture& m : mixtures) {
    if (m.size() == 1) {
      names.push_back(materials[m[0].first]);
      continue;
    }
    std::string n;
    for (const auto& [material, w] : m) {
      char weight[16];
      std::snprintf(weight, sizeof weight, "%.4g ", w);
      n += (n.empty() ? "" : " + ") + std::string(weight) + materials[material];
    }
    names.push_back(n);
  }
  return names;
}

std::vector<GroundTruth> MixedSample::Truths(const std::vector<GroundTruth>& materials) const {
  std::vector<GroundTruth> out;
  for (const Mixture& m : mixtures) {
    if (m.size() == 1) {
      out.push_back(materials[m[0].first]);
      continue;
    }
    GroundTruth t;
    for (const auto& [material, w] : m) t.mix.push_back({&materials[material], w});
    out.push_back(t);
  }
  return out;
}

std::vector<MerlBrdf> MixedSample::Tables(const std::vector<MerlBrdf>& materials) const {
  std::vector<MerlBrdf> out;
  for (const Mixture& m : mixtures) {
    MerlBrdf t;
    for (std::size_t i = 0; i < t.raw.size(); ++i) {
      double sum = 0;
      bool data = true;
      for (const auto& [material, w] : m) {
        const double v = materials[material].raw[i];
        data = data && v >= 0;
        sum += w * v;
      }
      t.raw[i] = data ? sum : -1.0;
    }
    out.push_back(std::move(t));
  }
  return out;
}

MixedSample MakeSample(SampleKind kind, int width, int height, double size_mm, int materials,
                       std::uint64_t seed) {
  MixedSample s;
  if (kind == SampleKind::kCard) {
    s.layout = MakeCardLayout(width, height, size_mm, materials, seed);
    for (int m = 0; m < materials; ++m) s.mixtures.push_back({{m, 1.0}});
    return s;
  }
  if (materials < 2)
    throw UserError("--materials",
                    std::string("the ") + SampleKindName(kind) + " sample needs two materials");
  s.layout = EmptyLayout(width, height, size_mm);
  MixtureTable table(SampleKindName(kind));
  if (kind == SampleKind::kText) {
    table.Label({{0, 1.0}});
    table.Label({{1, 1.0}});
    DrawText(&s.layout, seed);
    s.mixtures = table.Take();
    return s;
  }
  const ValueNoise noise(seed);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double u = (x + 0.5) / width, v = (y + 0.5) / height;
      double w;  // the weight of material 1
      if (kind == SampleKind::kBlend) {
        w = u;
      } else {  // marble: stripes bent by turbulence
        w = 0.5 + 0.5 * std::sin(2 * M_PI * (3 * u + 2.5 * noise.At(4 * u, 4 * v)));
      }
      s.layout.label[std::size_t(y) * width + x] = table.Label({{0, 1 - w}, {1, w}});
    }
  s.mixtures = table.Take();
  return s;
}

MixedSample ReadSampleLabels(const std::string& path, int materials, double size_mm) {
  MixedSample s;
  std::vector<int> labels;
  int width = 0, height = 0;
  const bool exr = path.size() > 4 && path.substr(path.size() - 4) == ".exr";
  if (exr) {
    const FloatPlanes f = ReadFloatPlanesExr(path);
    const std::vector<float>& plane = f.Plane("label", path);
    for (std::size_t p = 0; p < plane.size(); ++p) {
      // A label is an index: a fraction or NaN is a file of weights or heights given by mistake.
      if (!std::isfinite(plane[p]) || std::abs(plane[p] - std::round(plane[p])) > 1e-3f)
        throw UserError(path, PixelName(p, f.width) + " has label " + std::to_string(plane[p]),
                        "labels are whole numbers, each a material's index in --materials "
                        "(mixtures go in a weight image)");
      labels.push_back(int(std::lround(plane[p])));
    }
    width = f.width, height = f.height;
  } else {
    const cv::Mat image = ReadGreyImage(path, "label image", "give an 8- or 16-bit grey PNG");
    cv::Mat wide;
    image.convertTo(wide, CV_32S);
    labels.assign(wide.begin<int>(), wide.end<int>());
    width = image.cols, height = image.rows;
  }
  if (width < 1 || height < 1) throw UserError(path, "the label image is empty");
  s.layout = EmptyLayout(width, height, size_mm);
  MixtureTable table(path);
  for (int m = 0; m < materials; ++m) table.Label({{m, 1.0}});
  for (std::size_t p = 0; p < labels.size(); ++p) {
    if (labels[p] < 0 || labels[p] >= materials)
      throw UserError(path,
                      PixelName(p, width) + " has label " + std::to_string(labels[p]) +
                          " but only " + std::to_string(materials) + " materials are given",
                      "give one material per label value, listed in that order (--materials, or "
                      "sim.materials in a plan)");
    s.layout.label[p] = std::uint8_t(labels[p]);
  }
  s.mixtures = table.Take();
  return s;
}

MixedSample ReadSampleWeights(const std::string& path, const std::vector<std::string>& materials,
                              double size_mm) {
  const FloatPlanes f = ReadFloatPlanesExr(path);
  std::vector<const std::vector<float>*> planes;
  for (const std::string& m : materials) planes.push_back(&f.Plane(m, path));
  MixedSample s;
  s.layout = EmptyLayout(f.width, f.height, size_mm);
  MixtureTable table(path);
  for (std::size_t p = 0; p < s.layout.label.size(); ++p) {
    Mixture m;
    double total = 0;
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const double w = (*planes[i])[p];
      if (!(w >= 0))
        throw UserError(path, PixelName(p, f.width) + ": the weight of " + materials[i] + " is " +
                                  std::to_string(w) + "; weights must be >= 0");
      total += w;
      m.push_back({int(i), w});
    }
    if (std::abs(total - 1) > 0.01)
      throw UserError(
          path, PixelName(p, f.width) + ": the weights sum to " + std::to_string(total) + ", not 1",
          "normalise the weights per pixel");
    s.layout.label[p] = table.Label(m);
  }
  s.mixtures = table.Take();
  return s;
}

MixedSample ReadSampleFile(const SampleFile& file, const std::vector<std::string>& materials,
                           double sample_size_mm) {
  switch (file.kind) {
    case SampleFile::Kind::kLabels:
      return ReadSampleLabels(file.path, int(materials.size()), sample_size_mm);
    case SampleFile::Kind::kWeights:
      return ReadSampleWeights(file.path, materials, sample_size_mm);
  }
  throw std::logic_error("ReadSampleFile: unknown file kind");
}

}  // namespace acq::sim
