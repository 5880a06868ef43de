// A height map integrated from a normal map (issue 19's optional output): the least-squares
// surface whose gradients are closest to the normals' (Frankot and Chellappa 1988, by the
// discrete Fourier transform; the map taken as periodic, its mean height 0). A normal is a
// slope only up to where it stays readable: gradients are clamped at 60 degrees, and a normal
// that is not finite or not facing up counts as flat.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace acq {

// `normals`: w x h, row-major, in the sample frame (x along the columns, y against the rows: the
// map's rows run to the sample's -y). Returns heights in units of a pixel's width, row-major.
std::vector<float> HeightFromNormals(const std::vector<Eigen::Vector3f>& normals, int w, int h);

}  // namespace acq
