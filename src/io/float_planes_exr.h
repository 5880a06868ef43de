// Whole-image OpenEXR files of named 32-bit float planes with string attributes: the format of
// the per-view maps (correspondence) that are small enough to hold whole. Written to a temporary
// name and renamed, so a crash never leaves a truncated file.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace acq {

struct FloatPlanes {
  int width = 0, height = 0;
  std::map<std::string, std::vector<float>> planes;  // width * height each, row-major
  std::map<std::string, std::string> attributes;

  const std::vector<float>& Plane(const std::string& name, const std::string& where) const;
};

void WriteFloatPlanesExr(const std::string& path, const FloatPlanes& image);
// UserError naming the file if it cannot be read. Without `read_pixels`, the size and the
// attributes only (the planes are left empty): a frame's metadata without its pixels.
FloatPlanes ReadFloatPlanesExr(const std::string& path, bool read_pixels = true);

}  // namespace acq
