#include "brdf/directions.h"

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "core/angles.h"
#include "core/error.h"
#include "core/gantry_geometry.h"

namespace acq {
namespace {

std::string Deg(double rad) {
  return DegString(rad, 1);
}

// Throws when a direction is below the horizon or lands in a masked bin.
void CheckAboveHorizon(const RusinkiewiczAngles& a, const std::string& where) {
  const DirectionPair d = DirectionsFromRusinkiewicz(a);
  const std::string angles = "theta_h " + Deg(a.theta_h) + ", theta_d " + Deg(a.theta_d) +
                             ", phi_d " + Deg(a.phi_d) + " deg";
  if (!AboveHorizon(d)) {
    throw UserError(where,
                    "direction (" + angles + ") is below the horizon: light zenith " +
                        Deg(std::acos(std::clamp(d.in.z(), -1.0, 1.0))) + ", camera zenith " +
                        Deg(std::acos(std::clamp(d.out.z(), -1.0, 1.0))) + " deg",
                    "both zenith angles must be under 90 degrees; reduce theta_h or theta_d");
  }
  if (!merl::Geometry().valid[merl::BinOf(a).Flat()]) {
    throw UserError(
        where, "direction (" + angles + ") falls in a MERL bin whose centre is below the horizon",
        "move it away from grazing");
  }
}

}  // namespace

std::vector<Direction> ReadDirectionsTsv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw UserError(path, "cannot open directions file", "check the path");
  std::vector<Direction> out;
  std::string line;
  bool header_seen = false;
  int extra_columns = 0;  // e.g. the arm angles that `acq directions optimize` writes
  for (int number = 1; std::getline(f, line); ++number) {
    const std::string where = path + ":" + std::to_string(number);
    if (line.empty() || line[0] == '#') continue;
    std::istringstream cols(line);
    if (!header_seen) {
      std::string a, b, c;
      cols >> a >> b >> c;
      if (a != "theta_h" || b != "theta_d" || c != "phi_d")
        throw UserError(
            where, "expected a header starting 'theta_h<TAB>theta_d<TAB>phi_d', got '" + line + "'",
            "add the header line before the directions");
      for (std::string extra; cols >> extra;) ++extra_columns;
      header_seen = true;
      continue;
    }
    double th, td, pd;
    int extra = 0;
    bool ok = bool(cols >> th >> td >> pd);
    for (double v; ok && cols >> v;) ++extra;
    if (!ok || !cols.eof() || extra != extra_columns)
      throw UserError(where, "expected " + std::to_string(3 + extra_columns) +
                                 " numbers (degrees) as in the header, got '" + line + "'");
    if (!(th >= 0 && th <= 90) || !(td >= 0 && td <= 90) || !(pd >= -180 && pd <= 360))
      throw UserError(where, "angle out of range in '" + line + "'",
                      "theta_h and theta_d in [0, 90], phi_d in [-180, 360] degrees");
    Direction d;
    d.angles.theta_h = DegToRad(th);
    d.angles.theta_d = DegToRad(td);
    d.angles.phi_d = DegToRad(pd > 180 ? pd - 360 : pd);
    d.where = where;
    CheckAboveHorizon(d.angles, where);
    out.push_back(d);
  }
  if (!header_seen || out.empty())
    throw UserError(path, "no directions in file", "one direction a line after the header");
  return out;
}

void WriteDirectionsTsv(const std::vector<Direction>& directions, const std::string& path,
                        const std::string& comment) {
  std::ofstream f(path);
  if (!f) throw UserError(path, "cannot create file", "check the folder exists and is writable");
  std::istringstream lines(comment);
  for (std::string l; std::getline(lines, l);) f << "# " << l << "\n";
  f << "theta_h\ttheta_d\tphi_d\tlight_theta_deg\tlight_phi_deg\tcamera_theta_deg\tcamera_phi_"
       "deg\n";
  f.precision(10);  // enough that a direction never changes MERL bin on a round trip
  for (const auto& d : directions) {
    double phi_d = RadToDeg(d.angles.phi_d);
    if (phi_d < 0) phi_d += 360;
    const ArmAngles arms = ArmAnglesFor(d.angles);
    f << RadToDeg(d.angles.theta_h) << "\t" << RadToDeg(d.angles.theta_d) << "\t" << phi_d << "\t"
      << RadToDeg(arms.light_theta) << "\t" << RadToDeg(arms.light_phi) << "\t"
      << RadToDeg(arms.camera_theta) << "\t" << RadToDeg(arms.camera_phi) << "\n";
  }
  if (!f) throw UserError(path, "write failed", "check free disk space");
}

std::vector<Direction> RandomDirections(int n, std::uint64_t seed) {
  if (n < 1) throw UserError("--n", "must be at least 1");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto hemisphere = [&] {
    const double z = u(rng), phi = 2 * kPi * u(rng), r = std::sqrt(1 - z * z);
    return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z);
  };
  std::vector<Direction> out;
  while (int(out.size()) < n) {
    const Eigen::Vector3d in = hemisphere(), out_dir = hemisphere();
    RusinkiewiczAngles a = RusinkiewiczFromDirections(in, out_dir);
    a.phi_h = 0;
    if (!merl::Geometry().valid[merl::BinOf(a).Flat()]) continue;
    out.push_back({a, "random(seed " + std::to_string(seed) + ")"});
  }
  return out;
}

std::vector<std::size_t> BinsOf(const std::vector<Direction>& directions) {
  std::vector<std::size_t> bins;
  for (const auto& d : directions) bins.push_back(merl::BinOf(d.angles).Flat());
  return bins;
}

}  // namespace acq
