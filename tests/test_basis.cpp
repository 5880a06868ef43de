#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <iterator>

#include "brdf/basis.h"
#include "brdf/basis_file.h"
#include "brdf/direction_optimizer.h"
#include "brdf/directions.h"
#include "brdf/evaluation.h"
#include "brdf/log_mapping.h"
#include "core/error.h"
#include "issue_split.h"
#include "test_helpers.h"

using namespace acq;

namespace {

MaterialSplit SmallSplit() {
  const std::string dir = test::DataPath("nbrdf/merl/");
  MaterialSplit s;
  for (const char* n : {"alum-bronze", "blue-fabric", "gold-paint", "pink-felt", "teflon"})
    s.training.push_back({n, dir + n + ".h5"});
  s.held_out.push_back({"brass", dir + "brass.h5"});
  return s;
}

// Built once and shared: 5 materials, 15 rows, every component kept.
const BasisData& SmallBasis() {
  static const BasisData basis = [] {
    BasisOptions o;
    o.components = 15;
    o.progress = false;
    return BuildBasis(SmallSplit(), o);
  }();
  return basis;
}

}  // namespace

TEST_CASE("reference and mean follow the definitions, bin by bin", "[basis]") {
  // Recompute rho_ref (median of the 15 cos-weighted channels) and mu (mean of the mapped
  // values) from the tabulated materials, independently of the builder's blocked loops.
  const BasisData& basis = SmallBasis();
  std::vector<MerlBrdf> tables;
  for (const auto& m : SmallSplit().training) tables.push_back(LoadMaterial(m));
  const auto& g = merl::Geometry();
  for (std::size_t i = 0; i < g.valid_bins.size(); i += 10007) {
    const std::uint32_t bin = g.valid_bins[i];
    std::vector<double> weighted;
    for (const auto& t : tables)
      for (int c = 0; c < 3; ++c)
        weighted.push_back(std::max(t.Value(c, bin), 0.0) * g.cos_weight[bin]);
    const double ref = Median(weighted);
    double mean = 0;
    for (double w : weighted) mean += MapBrdf(w, 1.0, ref) / 15.0;
    // Storage is float32: 1e-5 relative plus a small absolute margin for values near zero.
    REQUIRE(basis.ref[bin] == Approx(ref).epsilon(1e-5).margin(1e-7));
    REQUIRE(basis.mean[bin] == Approx(mean).epsilon(1e-5).margin(1e-5));
  }
  CHECK(basis.ref[merl::BinIndex{70, 60, 0}.Flat()] == 0.0f);  // masked bins stay zero
}

TEST_CASE("components are scaled by their singular values: Q^T Q = diag(s^2)", "[basis]") {
  const BasisData& basis = SmallBasis();
  const int k = basis.components;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(k, k);
  for (std::uint32_t bin : merl::Geometry().valid_bins) {
    const Eigen::Map<const Eigen::VectorXf> row(basis.q.data() + std::size_t(bin) * k, k);
    gram += row.cast<double>() * row.cast<double>().transpose();
  }
  const double s0 = basis.singular_values[0];
  for (int i = 0; i < k; ++i) {
    // Off-diagonals and diagonals relative to the largest: float32 rows over ~1.1M bins.
    CHECK(gram(i, i) == Approx(basis.singular_values[i] * basis.singular_values[i])
                            .epsilon(1e-4)
                            .margin(1e-6 * s0 * s0));
    for (int j = 0; j < i; ++j) CHECK(std::abs(gram(i, j)) < 1e-5 * s0 * s0);
  }
  for (int i = 1; i < k; ++i) CHECK(basis.singular_values[i] <= basis.singular_values[i - 1]);
}

TEST_CASE("a training material is reconstructed almost exactly from many directions", "[basis]") {
  // All 15 components, no ridge, 400 directions: the material lies in the span, so only
  // float32 storage of Q and mu limits the fit (1e-3 in log space is ~0.1% in the BRDF).
  const BasisData& basis = SmallBasis();
  RidgeOptions ridge;
  ridge.components = 15;
  ridge.eta = 1e-9;
  const auto errors = EvaluateHomogeneous(basis.View(), LoadMaterial(SmallSplit().training[2]),
                                          BinsOf(RandomDirections(400, 5)), ridge);
  for (const auto& e : errors) {
    CHECK(e.log_rmse < 1e-3);
    CHECK(e.relative_rmse < 1e-3);
  }
}

TEST_CASE("basis file: write, map, identical; corruption and truncation detected", "[basis]") {
  const BasisData& basis = SmallBasis();
  test::TempDir dir;
  const std::string path = dir / "b.acqb";
  WriteBasisFile(basis.View(), path);
  {
    const MappedBasis mapped = MappedBasis::Open(path);
    const BasisView& v = mapped.View();
    CHECK(v.components == basis.components);
    CHECK(v.training_rows == basis.training_rows);
    CHECK(std::memcmp(v.valid, basis.valid.data(), merl::kBins) == 0);
    CHECK(std::memcmp(v.ref, basis.ref.data(), 4 * merl::kBins) == 0);
    CHECK(std::memcmp(v.mean, basis.mean.data(), 4 * merl::kBins) == 0);
    CHECK(std::memcmp(v.q, basis.q.data(), basis.q.size() * 4) == 0);
    CHECK(std::vector<double>(v.singular_values.begin(), v.singular_values.end()) ==
          basis.singular_values);
    CHECK(v.settings == basis.settings);
    CHECK(std::string(v.settings).find("- teflon") != std::string::npos);
  }
  std::string bytes;
  {
    std::ifstream f(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(f), {});
  }
  std::string flipped = bytes;
  flipped[flipped.size() / 2] ^= 1;
  std::ofstream(dir / "flipped.acqb", std::ios::binary) << flipped;
  CHECK_THROWS_WITH(MappedBasis::Open(dir / "flipped.acqb"),
                    Catch::Contains("flipped.acqb") && Catch::Contains("checksum"));
  std::ofstream(dir / "short.acqb", std::ios::binary) << bytes.substr(0, bytes.size() - 10);
  CHECK_THROWS_WITH(MappedBasis::Open(dir / "short.acqb"), Catch::Contains("truncated"));
  std::ofstream(dir / "other.acqb", std::ios::binary) << std::string(200, 'x');
  CHECK_THROWS_WITH(MappedBasis::Open(dir / "other.acqb"), Catch::Contains("wrong magic"));
}

TEST_CASE("basis options are checked", "[basis]") {
  BasisOptions o;
  o.components = 16;
  CHECK_THROWS_WITH(o.Check(15), Catch::Contains("only 15 rows"));
  o.components = 0;
  CHECK_THROWS_AS(o.Check(15), UserError);
  RidgeOptions r;
  r.components = 16;
  CHECK_THROWS_WITH(r.Check(SmallBasis().View()), Catch::Contains("[1, 15]"));
}

// The issue's split: every tenth material by sorted name from the sixth held out, the basis
// from the other 90 (64 components, as `acq basis build` stores by default). Built once.
struct IssueSplit {
  MaterialSplit split;
  BasisData basis;
  std::vector<MerlBrdf> held;
};
const IssueSplit& Issue() {
  static const IssueSplit data = [] {
    IssueSplit d;
    d.split = test::IssueSplit();
    d.basis = test::IssueBasis(d.split);
    for (const auto& m : d.split.held_out) d.held.push_back(LoadMaterial(m));
    return d;
  }();
  return data;
}

// The paper's ridge solve (k = 20, eta = 40), which the issue's bar and the numpy reference are
// of; the product's defaults are chosen by cross-validation (kDefaultEta, basis.h).
RidgeOptions PapersRidge() {
  RidgeOptions ridge;
  ridge.components = 20;
  ridge.eta = 40;
  return ridge;
}

double MedianHeldOutError(const std::vector<std::size_t>& bins,
                          const RidgeOptions& ridge = PapersRidge()) {
  std::vector<double> errors;
  for (const auto& truth : Issue().held)
    for (const auto& e : EvaluateHomogeneous(Issue().basis.View(), truth, bins, ridge))
      errors.push_back(e.log_rmse);
  return Median(errors);
}

std::vector<std::size_t> SeedBins() {
  return BinsOf(ReadDirectionsTsv(test::DataPath("directions/seed_directions_20.tsv")));
}

TEST_CASE("held-out accuracy of the issue's split: seed directions beat random ones",
          "[basis][accuracy]") {
  // Seed's 20 directions, k = 20, eta = 40. An independent numpy implementation gives a median
  // log-space RMSE of about 0.19 (tools/reference_basis.py); the issue's bar is 0.21. Random sets
  // of 20 give about 0.4 or worse there, so 0.3 separates them with a wide margin.
  const double seed = MedianHeldOutError(SeedBins());
  WARN("seed directions: median log-space RMSE " << seed);
  CHECK(seed < 0.21);
  for (std::uint64_t s : {1, 2, 3}) {
    const double random = MedianHeldOutError(BinsOf(RandomDirections(20, s)));
    WARN("random directions (seed " << s << "): median log-space RMSE " << random);
    CHECK(random > 0.3);
  }
}

TEST_CASE("optimised 20 directions: condition number and held-out error no worse than the seed's",
          "[directions][accuracy]") {
  OptimizerOptions o;  // n = 20, k = 20, camera below 65 degrees, defaults otherwise
  o.progress = false;
  o.eta = PapersRidge().eta;  // optimised for the ridge it is scored with
  const OptimizedDirections ours = OptimizeDirections(Issue().basis.View(), o);
  const BasisView basis = Issue().basis.View();
  const double seed_condition = ConditionOfBins(basis, SeedBins(), 20);
  const double our_condition = ConditionOfBins(basis, BinsOf(ours.directions), 20);
  const double seed_error = MedianHeldOutError(SeedBins());
  const double our_error = MedianHeldOutError(BinsOf(ours.directions));
  WARN("condition number: ours " << our_condition << ", seed " << seed_condition);
  WARN("median held-out log-space RMSE: ours " << our_error << ", seed " << seed_error);
  CHECK(our_condition <= seed_condition);
  CHECK(our_error <= seed_error);
}
