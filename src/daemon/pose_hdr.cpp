#include "daemon/pose_hdr.h"

#include <cstdio>
#include <vector>

#include "core/error.h"
#include "core/seconds_since.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"

namespace acq {

std::string PoseName(const std::string& step, int pose) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%03d", step.c_str(), pose);
  return name;
}

std::map<int, PoseHdr> MergeStep(const std::string& step, SessionCatalog& catalog,
                                 double* seconds) {
  const auto start = SteadyClock::now();
  const std::string dir = catalog.directory();
  std::map<int, std::vector<CatalogFrame>> by_pose;
  for (const CatalogFrame& f : catalog.Frames())
    if (f.step == step) by_pose[f.pose].push_back(f);
  std::map<int, PoseHdr> merged;
  for (const auto& [pose, frames] : by_pose) {
    std::vector<Frame> bracket;
    std::map<std::string, std::string> attributes;
    for (const CatalogFrame& f : frames)
      bracket.push_back(ReadFrameExr(dir + "/" + f.path, &attributes));
    PoseHdr& p = merged[pose];
    p.hdr = MergeBracket(bracket, {});
    p.arms = ParseArmAnglesAttribute(attributes["arms_measured_deg"], frames.front().path);
    p.direction = attributes["direction"];
    FloatPlanes file;
    file.width = p.hdr.width;
    file.height = p.hdr.height;
    file.planes["radiance"] = p.hdr.radiance;
    file.planes["flag"].assign(p.hdr.flag.begin(), p.hdr.flag.end());
    file.attributes["unit"] = "counts per microsecond at 0 dB";
    WriteFloatPlanesExr(dir + "/hdr/" + PoseName(step, pose) + ".exr", file);
  }
  *seconds += SecondsSince(start);
  return merged;
}

}  // namespace acq
