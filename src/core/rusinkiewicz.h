// Rusinkiewicz (1998) half/difference coordinates of a pair of directions.
//
// Frame: the local surface frame (for the sample: the sample frame), z along the normal.
// Directions point away from the surface. The light direction is "in" (w_i), the camera
// direction "out" (w_o); the BRDFs we handle are reciprocal, so swapping them only maps
// phi_d to phi_d + pi, which the MERL binning folds away.
#pragma once

#include <Eigen/Core>

namespace acq {

struct RusinkiewiczAngles {
  double theta_h = 0;  // zenith of the half vector, [0, pi/2] above the horizon
  double phi_h = 0;    // azimuth of the half vector; free for isotropic BRDFs
  double theta_d = 0;  // zenith of w_i in the half-vector frame, [0, pi/2]
  double phi_d = 0;    // azimuth of w_i in the half-vector frame, (-pi, pi]
};

struct DirectionPair {
  Eigen::Vector3d in;   // towards the light, unit
  Eigen::Vector3d out;  // towards the camera, unit
};

// Both vectors must be unit length and not opposite (their sum defines the half vector).
// When the half vector is the normal (theta_h = 0), phi_h is taken as 0.
RusinkiewiczAngles RusinkiewiczFromDirections(const Eigen::Vector3d& in,
                                              const Eigen::Vector3d& out);
// The same without phi_h (left 0): what an isotropic BRDF's bin needs, one atan2 fewer (the
// per-pixel solve converts every observation).
RusinkiewiczAngles IsotropicAnglesFromDirections(const Eigen::Vector3d& in,
                                                 const Eigen::Vector3d& out);

// Inverse of RusinkiewiczFromDirections: rotates the difference vector back out of the
// half-vector frame.
DirectionPair DirectionsFromRusinkiewicz(const RusinkiewiczAngles& a);

// True when both directions lie strictly above the surface (z > 0).
bool AboveHorizon(const DirectionPair& d);

// Unit vector at zenith theta, azimuth phi (z up), and the zenith angle of a vector; atan2 keeps
// full precision near the pole, where acos loses half the digits.
Eigen::Vector3d SphericalDirection(double theta, double phi);
double ZenithOf(const Eigen::Vector3d& v);

// The difference vector in the half-vector frame: the second half of the neural-BRDF input.
Eigen::Vector3d DifferenceVector(double theta_d, double phi_d);

}  // namespace acq
