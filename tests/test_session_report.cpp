// The session report's normals section (session/report.h): what the search did, and a warning
// a person cannot miss when much of the sample refused a normal (relief too steep).
#include <catch2/catch.hpp>

#include <string>

#include "session/report.h"

using namespace acq;

namespace {

SessionReport WithNormals(long pixels, long refused) {
  SessionReport r;
  ReconstructionReport& m = r.process.reconstruction;
  m.normals_searched = true;
  m.normals_max_tilt_deg = 25;
  m.pixels = m.valid = pixels;
  m.normals_refused = refused;
  m.normals_estimated = pixels - refused;
  return r;
}

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("the report counts the normal search's outcomes and warns when many are refused",
          "[report]") {
  // 7.8% refused: the embossed card at 40 degrees through acqd.
  const SessionReport steep = WithNormals(65536, 5120);
  CHECK(Has(steep.Json(), "\"refused\": 5120"));
  CHECK(Has(steep.Json(), "\"many_refused\": true"));
  CHECK(Has(steep.Text(), "normals: 60416 estimated, 5120 refused"));
  CHECK(Has(steep.Text(),
            "WARNING: 7.8% of the pixels refused a normal: relief steeper than "
            "the search's 25 degree cone"));
  // 2.0% refused: the same card at 10 degrees (ink edges where the data cannot tell).
  const SessionReport embossed = WithNormals(65536, 1285);
  CHECK(Has(embossed.Json(), "\"many_refused\": false"));
  CHECK(Has(embossed.Text(), "1285 refused"));
  CHECK_FALSE(Has(embossed.Text(), "WARNING"));
}

TEST_CASE("a report without the normal search has no normals section", "[report]") {
  SessionReport r;
  r.process.reconstruction.pixels = r.process.reconstruction.valid = 100;
  CHECK_FALSE(Has(r.Json(), "many_refused"));
  CHECK_FALSE(Has(r.Text(), "normals:"));
}
