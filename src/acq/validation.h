// Validation views (issue 8; Yu et al. Fig. 5): light/view pairs captured like the sample's but
// not used for the reconstruction. The map predicts what each should have shown; the capture
// says what it did show. Both are compared in the reference view's pixels as BRDF values times
// cos(theta_i) (radiance per unit irradiance at normal incidence), each pixel with the light and
// view directions it really had in that view (its correspondence map).
#pragma once

#include <string>

#include "acq/correspondence_source.h"
#include "acq/map_render.h"
#include "brdf/basis_rows.h"
#include "io/svbrdf_map.h"

namespace acq {

struct ValidationResult {
  std::string name;
  long pixels = 0;             // compared: valid in the map, usable in the capture
  double relative_rms = 0;     // ||predicted - captured|| / ||captured|| over those pixels
  double median_relative = 0;  // median over those pixels of |predicted - captured| / captured
  // Median over those pixels of CIEDE2000 between pi x predicted and pi x captured as linear
  // Rec. 709 reflectances (a white Lambertian lit along its normal is 1); a mono camera's grey
  // differs in lightness only.
  double median_delta_e2000 = 0;
  RgbImage predicted, captured;  // rho cos(theta_i), reference pixels; 0 where not compared
};

// Throws UserError when the view's maps do not match the map's size.
ValidationResult CompareWithCapture(const SvbrdfMap& map, const BasisView& basis, SessionView view,
                                    RowLookup lookup);

}  // namespace acq
