// The map's normals scored against the truth (acq/map_score.h): a flat sample's false tilt per
// true material, so that one material's tilted patch is seen where the whole sample's median
// hides it.
#include <catch2/catch.hpp>
#include <cmath>

#include "acq/map_score.h"
#include "brdf/normal_search.h"
#include "core/angles.h"
#include "io/svbrdf_map.h"

using namespace acq;

namespace {

// A map of `pixels` pixels in a row, every plane 0; `plane(name)` is its values.
struct RowMap {
  SvbrdfMap map;
  std::vector<std::string> names = SvbrdfChannelNames(1);
  explicit RowMap(int pixels) {
    map.info.width = pixels, map.info.height = 1, map.info.components = 1;
    map.planes.assign(names.size(), std::vector<float>(std::size_t(pixels), 0.0f));
  }
  std::vector<float>& plane(const std::string& n) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return map.planes[i];
    FAIL("no plane " << n);
    return map.planes[0];
  }
};

}  // namespace

TEST_CASE("false tilt is scored per material on a flat sample", "[normals]") {
  RowMap row(5);
  SvbrdfMap& map = row.map;
  auto plane = [&](const std::string& n) -> std::vector<float>& { return row.plane(n); };
  // Pixels 0-2 are material 0, flat; 3-4 material 1, tilted 1 degree about y.
  const float tilt = float(DegToRad(1.0));
  for (int p = 0; p < 5; ++p) {
    plane("normal.x")[p] = p >= 3 ? std::sin(tilt) : 0.0f;
    plane("normal.z")[p] = p >= 3 ? std::cos(tilt) : 1.0f;
    plane("normal_status")[p] =
        float(p >= 3 ? NormalStatus::kEstimated : NormalStatus::kNoEvidence);
  }
  const std::vector<Eigen::Vector3f> truth(5, Eigen::Vector3f::UnitZ());
  const NormalScore s = ScoreNormals(map, truth, {0, 0, 0, 1, 1});
  CHECK(s.relief_pixels == 0);
  CHECK(std::isnan(s.median_error_deg_relief));
  CHECK(s.flat_pixels == 5);
  CHECK(s.no_evidence == 3);
  CHECK(s.median_tilt_deg_flat == Approx(0).margin(1e-6));  // the median hides material 1
  REQUIRE(s.material_median_tilt_deg_flat.size() == 2);
  CHECK(s.material_median_tilt_deg_flat[0] == Approx(0).margin(1e-6));
  CHECK(s.material_median_tilt_deg_flat[1] == Approx(1.0).epsilon(1e-4));
}

TEST_CASE("the relief's error is split by the normals' uncertainty", "[normals]") {
  // Four relief pixels tilted 5 degrees, all estimated flat (5 degrees off): uncertainties 0.5
  // and 1 (certain), 3.3, and -1 (a map written before the plane: left out of the split).
  RowMap row(4);
  const std::vector<float> radius = {0.5f, 1.0f, 3.3f, -1.0f};
  for (int p = 0; p < 4; ++p) {
    row.plane("normal.z")[std::size_t(p)] = 1;
    row.plane("normal_status")[std::size_t(p)] = float(NormalStatus::kEstimated);
    row.plane("normal_uncertainty_deg")[std::size_t(p)] = radius[std::size_t(p)];
  }
  const float tilt = float(DegToRad(5.0));
  const std::vector<Eigen::Vector3f> truth(4, {std::sin(tilt), 0.0f, std::cos(tilt)});
  const NormalScore s = ScoreNormals(row.map, truth);
  CHECK(s.relief_pixels == 4);
  CHECK(s.relief_pixels_certain == 2);
  CHECK(s.relief_pixels_uncertain == 1);
  CHECK(s.median_error_deg_relief_certain == Approx(5.0).epsilon(1e-4));
  CHECK(s.median_uncertainty_deg == Approx(1.0));
}
