// The SVBRDF map: one OpenEXR file per reconstruction, pixels of the reference view
// (docs/svbrdf-map.md). Channels, all 32-bit float: "R.c00".."R.cNN", "G.c..", "B.c.." (the k
// basis coefficients per colour channel), "valid" (1 trustworthy, 0 not), "observations" (views
// used), "condition" (of the pixel's sampled rows; inf when fewer views than components),
// "residual" (RMS log-space misfit at the observations), "group" (the pooled reconstruction's
// material group of the pixel, -1 when solved alone), "departure" (RMS log-space distance of the
// pixel's BRDF from its group's centre), "normal.x", "normal.y", "normal.z" (the pixel's shading
// normal in the sample frame, its tangent space; (0, 0, 1) unless estimated) and
// "normal_status" (brdf/normal_search.h NormalStatus: 0 assumed, 1 estimated, 2 refused, 3 no
// evidence for a tilt) and "normal_uncertainty_deg" (PixelNormals::uncertainty_deg: how far from
// the estimate lie normals the data cannot tell from it; -1 where none was estimated). Header
// attributes name the basis and its checksum, the solve settings, the reference camera model and
// the pixel size on the sample.
//
// Written band by band in increasing y, so a 16-megapixel map never has to be in memory whole;
// to a temporary name, renamed when complete, so a crash never leaves a truncated map.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace acq {

// The camera_model of a map from `acq reconstruct synthetic` (observations straight from the
// ground truth): how a reader tells a synthetic map from a session's.
inline constexpr const char* kSyntheticCameraModel =
    "none (synthetic: ideal pinhole looking straight down)";

struct SvbrdfMapInfo {
  int width = 0, height = 0;
  int components = 0;             // k
  double eta = 0;                 // ridge strength used
  std::string lookup;             // "nearest" or "interpolated"
  std::string basis;              // path of the basis file
  std::uint32_t basis_crc32 = 0;  // its checksum (docs/basis-format.md)
  std::string camera_model;       // reference camera's .cameramodel, or kSyntheticCameraModel
  double pixel_size_mm = 0;       // on the sample
  // The spread of the points a camera pixel integrated over (core/pixel_footprint.h), in map
  // pixels: the map's renders average each pixel over it where its normals vary
  // (acq/map_render.h, MapBrdfAt). 0: point sampling, and every map written before it.
  double pixel_spread_px = 0;
  std::string source;                  // what the observations came from
  std::string method = "independent";  // ReconstructionMethodName
  std::string model;                   // the pooled model's summary (PooledModel::Summary)
  // Written as the attribute acqRowRule: the map's rows run to the sample's -y
  // (core/sample_grid.h). False only to write a file as maps were before the rule (tests).
  bool rows_to_minus_y = true;
};

// Channel names in file order: 3 k coefficient channels, then the ten per-pixel diagnostics.
// Maps written before "group", "departure" and the normal existed read with -1, 0 and a flat,
// assumed normal there.
std::vector<std::string> SvbrdfChannelNames(int components);

class SvbrdfMapWriter {
 public:
  SvbrdfMapWriter(const std::string& path, const SvbrdfMapInfo& info);
  ~SvbrdfMapWriter();  // without Finish(), the partial file is removed
  // The next `rows` rows: one plane of rows * width floats per channel, in SvbrdfChannelNames
  // order.
  void WriteRows(int rows, const std::vector<const float*>& planes);
  void Finish();  // all rows written: close and move into place

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct SvbrdfMap {
  SvbrdfMapInfo info;
  std::vector<std::vector<float>> planes;  // SvbrdfChannelNames order, width * height each
  // Coefficients of pixel (x, y), channel c (0..2): k values.
  std::vector<float> Coefficients(int x, int y, int channel) const;
  float Plane(const std::string& name, int x, int y) const;
};

// Throws UserError naming the file when it is not an SVBRDF map or is incomplete. A synthetic
// map written before the row rule (no acqRowRule; `acq reconstruct synthetic` then ran its rows
// to +y) is read with its rows turned over, so that every pixel keeps its place on the sample;
// a session's map always ran its rows to -y and is read as written.
SvbrdfMap ReadSvbrdfMap(const std::string& path);

}  // namespace acq
