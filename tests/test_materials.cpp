#include <catch2/catch.hpp>

#include "brdf/materials.h"
#include "core/error.h"
#include "test_helpers.h"

using namespace acq;

TEST_CASE("the shipped fits list sorted, and the issue's hold-out rule", "[materials]") {
  const auto all = ListMaterials({test::DataPath("nbrdf/merl")});
  REQUIRE(all.size() == 100);
  CHECK(all.front().name == "alum-bronze");
  CHECK(all.back().name == "yellow-plastic");
  HoldOut h;
  h.every = 10;
  h.offset = 5;  // the sixth, 0-based
  const MaterialSplit split = SplitMaterials(all, h);
  CHECK(split.training.size() == 90);
  // `ls data/nbrdf/merl | LC_ALL=C sort | sed -n '6~10p'`
  const std::vector<std::string> expected = {
      "black-fabric", "brass",        "dark-specular-fabric",    "green-fabric",     "natural-209",
      "pink-jasper",  "red-phenolic", "specular-green-phenolic", "tungsten-carbide", "white-paint"};
  REQUIRE(split.held_out.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) CHECK(split.held_out[i].name == expected[i]);
}

TEST_CASE("material set errors", "[materials]") {
  test::TempDir dir;
  CHECK_THROWS_WITH(ListMaterials({dir / ""}), Catch::Contains("empty material set"));
  CHECK_THROWS_WITH(ListMaterials({dir / "nope"}), Catch::Contains("no such file"));
  const std::string one = test::DataPath("nbrdf/merl/brass.h5");
  CHECK_THROWS_WITH(ListMaterials({one, one}), Catch::Contains("given twice"));
  HoldOut h;
  h.names = {"no-such-material"};
  CHECK_THROWS_WITH(SplitMaterials(ListMaterials({one}), h), Catch::Contains("no-such-material"));
  h.names = {"brass"};
  CHECK_THROWS_WITH(SplitMaterials(ListMaterials({one}), h), Catch::Contains("nothing is left"));
}
