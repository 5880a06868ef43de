#include "acq/map_score.h"

#include <Eigen/Core>

#include "brdf/evaluation.h"
#include "brdf/fov_evaluation.h"
#include "core/error.h"

namespace acq {

MapScore ScoreMap(const SvbrdfMap& map, const BasisView& basis, const std::vector<int>& label,
                  const std::vector<MerlBrdf>& truth) {
  const int w = map.info.width, h = map.info.height, k = map.info.components;
  if (label.size() != std::size_t(w) * std::size_t(h))
    throw UserError("ground truth", "has " + std::to_string(label.size()) +
                                        " labels for a map of " + std::to_string(w) + " x " +
                                        std::to_string(h) + " pixels");
  if (basis.components < k)
    throw UserError("basis", "has fewer components than the map (" + std::to_string(k) + ")",
                    "give the basis the map was reconstructed with (" + map.info.basis + ")");
  const HeldOutSet held(basis, truth);
  MapScore score;
  score.log_rmse.assign(label.size(), -1.0f);
  std::vector<double> all, valid;
  std::vector<std::vector<double>> by_material(truth.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * w + x;
      if (label[p] < 0) continue;
      const bool is_valid = map.Plane("valid", x, y) != 0;
      double sum = 0;
      for (int c = 0; c < 3; ++c) {
        const std::vector<float> cf = map.Coefficients(x, y, c);
        const Eigen::Map<const Eigen::VectorXf> coeff(cf.data(), k);
        const double e = held.LogRmse(label[p] * 3 + c, coeff.cast<double>());
        all.push_back(e);
        if (is_valid) valid.push_back(e);
        sum += e;
      }
      score.log_rmse[p] = float(sum / 3);
      by_material.at(std::size_t(label[p])).push_back(sum / 3);
      ++score.pixels;
      score.valid += is_valid;
    }
  for (const std::vector<double>& m : by_material)
    score.material_median_log_rmse.push_back(m.empty() ? 0 : Median(m));
  score.median_log_rmse = all.empty() ? 0 : Median(all);
  score.median_log_rmse_valid = valid.empty() ? 0 : Median(valid);
  return score;
}

}  // namespace acq
