#include "io/float_planes_exr.h"

#include <filesystem>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include "core/error.h"
#include "io/exr_settings.h"

namespace acq {

const std::vector<float>& FloatPlanes::Plane(const std::string& name,
                                             const std::string& where) const {
  const auto it = planes.find(name);
  if (it == planes.end())
    throw UserError(where, "has no channel '" + name + "'",
                    "regenerate the file with this version");
  return it->second;
}

void WriteFloatPlanesExr(const std::string& path, const FloatPlanes& image) {
  Imf::Header header(image.width, image.height);
  header.compression() = kExrCompression;
  UseExrThreads();
  Imf::FrameBuffer fb;
  for (const auto& [name, plane] : image.planes) {
    if (plane.size() != static_cast<std::size_t>(image.width) * image.height)
      throw std::logic_error("WriteFloatPlanesExr: plane " + name + " has the wrong size");
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    fb.insert(name, Imf::Slice(Imf::FLOAT, (char*)plane.data(), sizeof(float),
                               sizeof(float) * image.width));
  }
  for (const auto& [key, value] : image.attributes) header.insert(key, Imf::StringAttribute(value));
  const std::string partial = path + ".partial.exr";
  try {
    Imf::OutputFile file(partial.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    std::filesystem::remove(partial);
    throw UserError(path, std::string("could not write: ") + e.what(),
                    "check the folder exists and has space");
  }
  std::filesystem::rename(partial, path);
}

FloatPlanes ReadFloatPlanesExr(const std::string& path, bool read_pixels) {
  FloatPlanes out;
  try {
    UseExrThreads();
    Imf::InputFile file(path.c_str());
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    out.width = dw.max.x - dw.min.x + 1;
    out.height = dw.max.y - dw.min.y + 1;
    for (auto it = h.begin(); it != h.end(); ++it)
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        out.attributes[it.name()] = s->value();
    if (!read_pixels) return out;
    Imf::FrameBuffer fb;
    for (auto c = h.channels().begin(); c != h.channels().end(); ++c) {
      std::vector<float>& plane = out.planes[c.name()];
      plane.assign(static_cast<std::size_t>(out.width) * out.height, 0.f);
      char* base = (char*)(plane.data() - dw.min.x - std::ptrdiff_t(dw.min.y) * out.width);
      fb.insert(c.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * out.width));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const std::exception& e) {
    throw UserError(path, std::string("cannot read as OpenEXR: ") + e.what(),
                    "check the path; the file may be incomplete");
  }
  return out;
}

}  // namespace acq
