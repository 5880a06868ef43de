#include "brdf/neural_brdf.h"

#include <hdf5.h>

#include <cmath>
#include <mutex>
#include <vector>

#include "core/angles.h"
#include "core/error.h"

namespace acq {
namespace {

// The HDF5 library is not thread-safe in Debian's serial build; one lock guards all calls.
std::mutex& Hdf5Mutex() {
  static std::mutex m;
  return m;
}

struct H5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~H5Handle() {
    if (id >= 0) close(id);
  }
};

NeuralBrdf::RowMatrix ReadDataset(hid_t file, const std::string& path, const std::string& name,
                                  hsize_t rows, hsize_t cols) {
  const std::string where = path + ": dataset " + name;
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) {
    // Check each level so the message names the missing group.
    throw UserError(where, "is missing",
                    "expected a Keras 6-21-21-3 neural-BRDF weights file (data/nbrdf/README.md)");
  }
  H5Handle ds{H5Dopen2(file, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (ds.id < 0) throw UserError(where, "cannot be opened as a dataset");
  H5Handle space{H5Dget_space(ds.id), H5Sclose};
  const int ndims = H5Sget_simple_extent_ndims(space.id);
  hsize_t dims[2] = {0, 0};
  if (ndims < 1 || ndims > 2) throw UserError(where, "has " + std::to_string(ndims) + " dims");
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  const hsize_t got_rows = ndims == 1 ? 1 : dims[0];
  const hsize_t got_cols = ndims == 1 ? dims[0] : dims[1];
  const bool want_vector = rows == 1;
  if ((want_vector && ndims != 1) || got_rows != rows || got_cols != cols) {
    auto shape = [&](hsize_t r, hsize_t c, bool vec) {
      return vec ? "(" + std::to_string(c) + ",)"
                 : "(" + std::to_string(r) + ", " + std::to_string(c) + ")";
    };
    throw UserError(where,
                    "has shape " + shape(got_rows, got_cols, ndims == 1) + ", expected " +
                        shape(rows, cols, want_vector),
                    "this is not a 6-21-21-3 neural-BRDF fit");
  }
  NeuralBrdf::RowMatrix m(rows, cols);
  if (H5Dread(ds.id, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data()) < 0)
    throw UserError(where, "could not be read as float", "the file may be corrupt");
  if (!m.allFinite()) throw UserError(where, "contains NaN or Inf", "the fit is corrupt");
  return m;
}

}  // namespace

NeuralBrdf NeuralBrdf::Load(const std::string& path) {
  std::lock_guard<std::mutex> lock(Hdf5Mutex());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // we report errors ourselves
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw UserError(path, "is not an HDF5 file (or cannot be read)",
                    "expected a Keras neural-BRDF weights file (.h5)");
  H5Handle file{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (file.id < 0) throw UserError(path, "cannot be opened as HDF5");
  NeuralBrdf n;
  n.w1_ = ReadDataset(file.id, path, "dense_1/dense_1/kernel:0", kInputs, kHidden);
  n.b1_ = ReadDataset(file.id, path, "dense_1/dense_1/bias:0", 1, kHidden);
  n.w2_ = ReadDataset(file.id, path, "dense_2/dense_2/kernel:0", kHidden, kHidden);
  n.b2_ = ReadDataset(file.id, path, "dense_2/dense_2/bias:0", 1, kHidden);
  n.w3_ = ReadDataset(file.id, path, "dense_3/dense_3/kernel:0", kHidden, kOutputs);
  n.b3_ = ReadDataset(file.id, path, "dense_3/dense_3/bias:0", 1, kOutputs);
  return n;
}

std::array<float, NeuralBrdf::kInputs> NeuralBrdf::Input(const RusinkiewiczAngles& a) {
  // The fits were trained on MERL's tables, whose phi_d lies in [0, pi): fold by reciprocity
  // (phi_d -> phi_d + pi) as MERL's binning does, rather than extrapolate the network.
  const double phi_d = a.phi_d < 0 ? a.phi_d + kPi : a.phi_d;
  const Eigen::Vector3d d = DifferenceVector(a.theta_d, phi_d);
  return {float(std::sin(a.theta_h)),
          0.0f,
          float(std::cos(a.theta_h)),
          float(d.x()),
          float(d.y()),
          float(d.z())};
}

NeuralBrdf::RowMatrix NeuralBrdf::EvaluateBatch(const RowMatrix& inputs) const {
  RowMatrix h1 = ((inputs * w1_).rowwise() + b1_).cwiseMax(0.0f);
  RowMatrix h2 = ((h1 * w2_).rowwise() + b2_).cwiseMax(0.0f);
  RowMatrix y = (h2 * w3_).rowwise() + b3_;
  return y.array().expm1().matrix();  // exp(y) - 1 without cancellation for small y
}

std::array<double, 3> NeuralBrdf::Evaluate(const RusinkiewiczAngles& a) const {
  const auto in = Input(a);
  RowMatrix x(1, kInputs);
  for (int i = 0; i < kInputs; ++i) x(0, i) = in[i];
  const RowMatrix y = EvaluateBatch(x);
  return {y(0, 0), y(0, 1), y(0, 2)};
}

MerlBrdf NeuralBrdf::Tabulate() const {
  // The network inputs at the valid bin centres are the same for every material: build once.
  static const RowMatrix kGridInputs = [] {
    const auto& bins = merl::Geometry().valid_bins;
    RowMatrix x(bins.size(), kInputs);
    for (std::size_t r = 0; r < bins.size(); ++r) {
      const auto in = Input(merl::BinCentre(merl::BinFromFlat(bins[r])));
      for (int i = 0; i < kInputs; ++i) x(r, i) = in[i];
    }
    return x;
  }();
  const auto& bins = merl::Geometry().valid_bins;
  MerlBrdf brdf;                         // every bin starts as -1, "no data"
  constexpr Eigen::Index kBatch = 8192;  // keeps the hidden activations in cache
  for (Eigen::Index start = 0; start < kGridInputs.rows(); start += kBatch) {
    const Eigen::Index n = std::min(kBatch, kGridInputs.rows() - start);
    const RowMatrix rgb = EvaluateBatch(kGridInputs.middleRows(start, n));
    for (Eigen::Index r = 0; r < n; ++r)
      for (int c = 0; c < 3; ++c) brdf.SetValue(c, bins[start + r], std::max(rgb(r, c), 0.0f));
  }
  return brdf;
}

}  // namespace acq
