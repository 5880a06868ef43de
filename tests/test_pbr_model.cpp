// The analytic model's fit (issue 20): simulation first, a target made by the model itself
// recovered, with noise to a tolerance, and targets the fit must survive without NaN.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "brdf/pbr_model.h"
#include "core/merl_grid.h"

using namespace acq;

namespace {

std::vector<float> TargetOf(const PbrFitGrid& grid, const PbrParameters& p) {
  std::vector<float> t(3 * grid.Size());
  for (std::size_t n = 0; n < grid.Size(); ++n) {
    const DirectionPair d =
        DirectionsFromRusinkiewicz(merl::BinCentre(merl::BinFromFlat(grid.bins[n])));
    const auto f = EvaluatePbr(p, d.in, d.out);
    for (int c = 0; c < 3; ++c) t[3 * n + c] = float(f[c]);
  }
  return t;
}

const PbrFitGrid& Grid() {
  static const PbrFitGrid grid =
      PbrFitGrid::Default(merl::Geometry().valid.data(), 80 * 3.14159265358979323846 / 180);
  return grid;
}

}  // namespace

TEST_CASE("pbr fit: the model's own BRDF is recovered, glossy and rough", "[pbr]") {
  REQUIRE(Grid().Size() > 500);
  for (const PbrParameters& truth : {PbrParameters{{0.6, 0.5, 0.3}, {0.04, 0.04, 0.04}, 0.3},
                                     PbrParameters{{0.05, 0.1, 0.02}, {0.9, 0.6, 0.3}, 0.08},
                                     PbrParameters{{0.2, 0.2, 0.2}, {0.02, 0.03, 0.05}, 0.8}}) {
    const PbrFit fit = FitPbr(Grid(), TargetOf(Grid(), truth).data(), PbrFitOptions{});
    INFO("roughness " << truth.roughness << " fitted " << fit.parameters.roughness);
    CHECK(fit.converged);
    // Exact data: the fit reaches it to the float rounding of the target (1e-7 relative).
    CHECK(fit.log_rmse < 1e-3);
    // The default model has F90 and a coat, which these do not need: none is made up.
    CHECK(fit.parameters.coat == 0);
    CHECK(fit.parameters.specular == Approx(1).margin(0.005));
    CHECK(fit.parameters.roughness == Approx(truth.roughness).epsilon(0.01));
    for (int c = 0; c < 3; ++c) {
      CHECK(fit.parameters.diffuse[c] == Approx(truth.diffuse[c]).margin(0.005));
      CHECK(fit.parameters.f0[c] == Approx(truth.f0[c]).margin(0.005));
    }
  }
}

TEST_CASE("pbr fit: a lobe that does not rise to 1 at grazing is recovered by F90", "[pbr]") {
  // White paint's fit (docs/export.md): F90 0.14-0.3, F0 / F90 under 0.01.
  PbrParameters truth{{0.35, 0.33, 0.3}, {0.02, 0.02, 0.03}, 0.15};
  truth.specular = 0.25;
  const std::vector<float> t = TargetOf(Grid(), truth);
  PbrFitOptions schlick, weighted;
  schlick.model = PbrModel::kSchlick;
  weighted.model = PbrModel::kWeighted;
  const PbrFit without = FitPbr(Grid(), t.data(), schlick);
  const PbrFit with = FitPbr(Grid(), t.data(), weighted);
  CHECK(without.parameters.specular == 1);  // the model without F90 holds it
  // F90 = 1 cannot follow a Fresnel rise four times lower: the grazing bins miss by far more
  // than the float rounding the right model reaches.
  CHECK(without.log_rmse > 0.05);
  CHECK(with.log_rmse < 1e-3);
  CHECK(with.parameters.specular == Approx(truth.specular).epsilon(0.01));
  CHECK(with.parameters.roughness == Approx(truth.roughness).epsilon(0.01));
  for (int c = 0; c < 3; ++c) CHECK(with.parameters.f0[c] == Approx(truth.f0[c]).margin(0.002));
}

TEST_CASE("pbr fit: a peak over a broad shoulder takes a coat, and only then", "[pbr]") {
  // A glossy paint: a broad dim lobe and a sharp coat over it.
  PbrParameters truth{{0.3, 0.3, 0.3}, {0.05, 0.05, 0.05}, 0.5};
  truth.coat = 0.8;
  truth.coat_roughness = 0.08;
  const std::vector<float> t = TargetOf(Grid(), truth);
  PbrFitOptions weighted;
  weighted.model = PbrModel::kWeighted;
  const PbrFit one = FitPbr(Grid(), t.data(), weighted);
  const PbrFit coated = FitPbr(Grid(), t.data(), PbrFitOptions{});
  INFO("one lobe " << one.log_rmse << ", coated " << coated.log_rmse << " coat "
                   << coated.parameters.coat << " at " << coated.parameters.coat_roughness);
  CHECK(one.parameters.coat == 0);
  CHECK(one.log_rmse > 0.1);  // one lobe cannot follow both
  CHECK(coated.uncoated_log_rmse == Approx(one.log_rmse).epsilon(1e-6));
  // Exact data and the right model: a minimum at the float rounding, but the coat's starts are
  // the fit's guesses, so a local minimum near it is allowed (under a tenth of one lobe's).
  CHECK(coated.log_rmse < 0.01);
  CHECK(coated.parameters.coat == Approx(truth.coat).epsilon(0.05));
  CHECK(coated.parameters.coat_roughness == Approx(truth.coat_roughness).epsilon(0.05));
  CHECK(coated.parameters.roughness == Approx(truth.roughness).epsilon(0.05));
}

TEST_CASE("pbr fit: noise alone never buys a coat", "[pbr]") {
  // One lobe and 10% multiplicative noise: a coat can fit some of the noise, but never the
  // kPbrCoatMinGain (10%) of the RMS that it must buy to be kept.
  const PbrParameters truth{{0.4, 0.35, 0.3}, {0.04, 0.04, 0.04}, 0.25};
  for (unsigned seed : {1u, 2u, 3u}) {
    std::vector<float> t = TargetOf(Grid(), truth);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0, 0.1);
    for (float& v : t) v = float(v * std::exp(noise(rng)));
    const PbrFit fit = FitPbr(Grid(), t.data(), PbrFitOptions{});
    INFO("seed " << seed << ": " << fit.log_rmse << " against " << fit.uncoated_log_rmse);
    CHECK(fit.parameters.coat == 0);
    CHECK(fit.log_rmse == fit.uncoated_log_rmse);
  }
}

TEST_CASE("pbr fit: a lobe the fit leaves unused takes the other lobe's shape", "[pbr]") {
  // A renderer that blends neighbouring texels must blend weights, not invent a lobe from an
  // unused roughness: Lambert alone (no lobe to fit) and a lobe without a coat.
  const PbrParameters lambert{{0.5, 0.4, 0.3}, {0, 0, 0}, 0.3, 0.0};
  PbrParameters glossy{{0.3, 0.3, 0.3}, {0.04, 0.04, 0.04}, 0.2};
  for (const PbrParameters& truth : {lambert, glossy}) {
    const PbrFit fit = FitPbr(Grid(), TargetOf(Grid(), truth).data(), PbrFitOptions{});
    const PbrParameters& p = fit.parameters;
    INFO("specular " << p.specular << " coat " << p.coat << " roughness " << p.roughness);
    CHECK(fit.log_rmse < 0.01);
    if (p.coat == 0) CHECK(p.coat_roughness == p.roughness);
    if (p.specular == 0) {
      for (int c = 0; c < 3; ++c) CHECK(p.f0[c] == kPbrCoatF0);
      if (p.coat > 0) CHECK(p.roughness == p.coat_roughness);
    }
    // Weights under half an 8-bit step are zero: the texture would say so anyway.
    CHECK((p.specular == 0 || p.specular >= 0.5 / 255));
    CHECK((p.coat == 0 || p.coat >= 0.5 / 255));
  }
  // Lambert's fit has no lobe worth a texture step.
  const PbrFit none = FitPbr(Grid(), TargetOf(Grid(), lambert).data(), PbrFitOptions{});
  CHECK(none.parameters.specular == 0);
  CHECK(none.parameters.coat == 0);
}

TEST_CASE("pbr fit: the model's name is parsed, an unknown one refused", "[pbr]") {
  for (PbrModel m : {PbrModel::kSchlick, PbrModel::kWeighted, PbrModel::kCoated})
    CHECK(ParsePbrModel(PbrModelName(m), "--model") == m);
  CHECK_THROWS_WITH(ParsePbrModel("ggx2", "--model"), Catch::Contains("unknown model 'ggx2'"));
}

TEST_CASE("pbr fit: 5% multiplicative noise moves the parameters by about its mean", "[pbr]") {
  const PbrParameters truth{{0.5, 0.3, 0.2}, {0.05, 0.05, 0.05}, 0.2};
  std::vector<float> t = TargetOf(Grid(), truth);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.05);
  for (float& v : t) v = float(v * std::exp(noise(rng)));
  const PbrFit fit = FitPbr(Grid(), t.data(), PbrFitOptions{});
  CHECK(fit.converged);
  // The residual is the noise itself (0.05 in log space, less where eps flattens small values).
  CHECK(fit.log_rmse < 0.06);
  // About 1000 bins x 3 channels: 5% noise averages to well under 2% on each parameter.
  CHECK(fit.parameters.roughness == Approx(truth.roughness).epsilon(0.03));
  for (int c = 0; c < 3; ++c)
    CHECK(fit.parameters.diffuse[c] == Approx(truth.diffuse[c]).epsilon(0.03));
}

TEST_CASE("pbr fit: no finite value, zeros and huge values give finite parameters", "[pbr]") {
  std::vector<float> nan(3 * Grid().Size(), NAN);
  const PbrFit none = FitPbr(Grid(), nan.data(), PbrFitOptions{});
  CHECK_FALSE(none.converged);
  CHECK(none.log_rmse == 0);
  for (const float value : {0.0f, 1e30f}) {
    std::vector<float> t(3 * Grid().Size(), value);
    const PbrFit fit = FitPbr(Grid(), t.data(), PbrFitOptions{});
    CHECK(std::isfinite(fit.log_rmse));
    CHECK(std::isfinite(fit.parameters.roughness));
    for (int c = 0; c < 3; ++c) {
      CHECK(std::isfinite(fit.parameters.diffuse[c]));
      CHECK(fit.parameters.f0[c] >= 0);
      CHECK(fit.parameters.f0[c] <= 1);
    }
  }
}
