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
  for (const PbrParameters truth : {PbrParameters{{0.6, 0.5, 0.3}, {0.04, 0.04, 0.04}, 0.3},
                                    PbrParameters{{0.05, 0.1, 0.02}, {0.9, 0.6, 0.3}, 0.08},
                                    PbrParameters{{0.2, 0.2, 0.2}, {0.02, 0.03, 0.05}, 0.8}}) {
    const PbrFit fit = FitPbr(Grid(), TargetOf(Grid(), truth).data(), PbrFitOptions{});
    INFO("roughness " << truth.roughness << " fitted " << fit.parameters.roughness);
    CHECK(fit.converged);
    // Exact data: the fit reaches it to the float rounding of the target (1e-7 relative).
    CHECK(fit.log_rmse < 1e-3);
    CHECK(fit.parameters.roughness == Approx(truth.roughness).epsilon(0.01));
    for (int c = 0; c < 3; ++c) {
      CHECK(fit.parameters.diffuse[c] == Approx(truth.diffuse[c]).margin(0.005));
      CHECK(fit.parameters.f0[c] == Approx(truth.f0[c]).margin(0.005));
    }
  }
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
