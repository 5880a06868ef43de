#include "session/pose_hdr.h"

#include <cstdio>
#include <filesystem>

#include "acq/demosaic.h"
#include "core/error.h"
#include "core/seconds_since.h"
#include "hw/frame_file.h"
#include "io/float_planes_exr.h"
#include "session/hdr_thumbnail.h"

namespace acq {
namespace {

namespace fs = std::filesystem;

// A colour pose's planes in its hdr file (camera R, G, B, demosaiced); a mono pose's: "radiance".
constexpr const char* kColourPlanes[3] = {"R", "G", "B"};

std::string FrameList(const std::vector<CatalogFrame>& frames) {
  std::string list;
  for (const CatalogFrame& f : frames) list += (list.empty() ? "" : " ") + f.path;
  return list;
}

// The hdr file of these frames when it is up to date: it names them, is newer than each and was
// merged by this rule.
bool ReadUpToDate(const std::string& path, const std::string& dir,
                  const std::vector<CatalogFrame>& frames, PoseHdr* out) {
  std::error_code ec;
  const auto written = fs::last_write_time(path, ec);
  if (ec) return false;
  for (const CatalogFrame& f : frames) {
    const auto frame_time = fs::last_write_time(dir + "/" + f.path, ec);
    if (ec || frame_time > written) return false;
  }
  FloatPlanes file;
  try {
    file = ReadFloatPlanesExr(path);
  } catch (const UserError&) {
    return false;  // damaged: merged again
  }
  bool colour = true;
  for (const char* c : kColourPlanes) colour = colour && file.planes.count(c);
  if (file.attributes["frames"] != FrameList(frames) || file.attributes["merge"] != kHdrMergeRule ||
      !(colour || file.planes.count("radiance")) || !file.planes.count("flag"))
    return false;
  out->hdr.width = file.width;
  out->hdr.height = file.height;
  out->hdr.channels = colour ? 3 : 1;
  if (colour) {
    for (const char* c : kColourPlanes)
      out->hdr.radiance.insert(out->hdr.radiance.end(), file.planes[c].begin(),
                               file.planes[c].end());
  } else {
    out->hdr.radiance = std::move(file.planes["radiance"]);
  }
  out->hdr.flag.assign(file.planes["flag"].begin(), file.planes["flag"].end());
  out->arms = ParseArmAnglesAttribute(file.attributes["arms_measured_deg"], path);
  out->direction = file.attributes["direction"];
  return true;
}

}  // namespace

std::vector<CatalogFrame> SessionFrames::OfPose(Step step, int pose) const {
  std::vector<CatalogFrame> out;
  for (const CatalogFrame& f : frames)
    if (f.step == step && f.pose == pose) out.push_back(f);
  return out;
}

std::string PoseName(Step step, int pose) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%03d", ToString(step), pose);
  return name;
}

PoseHdr MergePose(const std::string& dir, Step step, int pose,
                  const std::vector<CatalogFrame>& frames, double* seconds) {
  const auto start = SteadyClock::now();
  const std::string path = dir + "/hdr/" + PoseName(step, pose) + ".exr";
  const std::string thumbnail = dir + "/hdr/" + PoseName(step, pose) + ".png";
  PoseHdr p;
  if (ReadUpToDate(path, dir, frames, &p)) {
    if (!fs::exists(thumbnail)) WriteHdrThumbnail(p.hdr, thumbnail);  // a session from before
  } else {
    std::vector<Frame> bracket;
    std::map<std::string, std::string> attributes;
    for (const CatalogFrame& f : frames)
      bracket.push_back(ReadFrameExr(dir + "/" + f.path, &attributes));
    // A colour camera's mosaic merged photosite by photosite, then demosaiced (demosaic.h).
    HdrImage mosaic = MergeBracket(bracket, {});
    const Cfa bracket_cfa = mosaic.cfa;
    p.hdr = Demosaic(std::move(mosaic));
    p.arms = ParseArmAnglesAttribute(attributes["arms_measured_deg"], frames.front().path);
    p.direction = attributes["direction"];
    FloatPlanes file;
    file.width = p.hdr.width;
    file.height = p.hdr.height;
    const std::size_t n = std::size_t(p.hdr.width) * std::size_t(p.hdr.height);
    if (p.hdr.channels == 3) {
      for (int c = 0; c < 3; ++c)
        file.planes[kColourPlanes[c]].assign(p.hdr.Plane(c), p.hdr.Plane(c) + n);
      file.attributes["colour"] = "camera RGB, demosaiced (" + std::string(CfaName(bracket_cfa)) +
                                  ", " + DemosaicMethodName(kDefaultDemosaic) + ")";
    } else {
      file.planes["radiance"] = p.hdr.radiance;
    }
    file.planes["flag"].assign(p.hdr.flag.begin(), p.hdr.flag.end());
    file.attributes["unit"] = "counts per microsecond at 0 dB";
    file.attributes["merge"] = kHdrMergeRule;
    file.attributes["frames"] = FrameList(frames);
    file.attributes["arms_measured_deg"] = attributes["arms_measured_deg"];
    file.attributes["direction"] = p.direction;
    fs::create_directories(dir + "/hdr");
    WriteFloatPlanesExr(path, file);
    WriteHdrThumbnail(p.hdr, thumbnail);
  }
  *seconds += SecondsSince(start);
  return p;
}

std::map<int, PoseHdr> MergeStep(Step step, const SessionFrames& session, double* seconds,
                                 std::map<std::pair<Step, int>, PoseHdr>* merged_before) {
  std::map<int, std::vector<CatalogFrame>> by_pose;
  for (const CatalogFrame& f : session.frames)
    if (f.step == step) by_pose[f.pose].push_back(f);
  std::map<int, PoseHdr> merged;
  for (const auto& [pose, frames] : by_pose) {
    if (merged_before) {
      if (auto known = merged_before->extract({step, pose})) {
        merged[pose] = std::move(known.mapped());
        continue;
      }
    }
    merged[pose] = MergePose(session.dir, step, pose, frames, seconds);
  }
  return merged;
}

}  // namespace acq
