// The simulated card's ground truth beside a session (ground_truth/), written by the simulated
// instrument and read back to score a map of it, by acqd or by `acq session process` on a
// finished session: the material label of every card cell (ground_truth_labels.exr, plane
// "material", attribute sampleSizeMm; with relief, planes "normal.x/y/z": each cell's true
// normal in the sample frame), the materials' names (materials.tsv: index, name) and the
// true camera model (camera.cameramodel).
#pragma once

#include <string>
#include <vector>

#include "calib/camera_model.h"
#include "sim/sample_renderer.h"

namespace acq::sim {

void WriteGroundTruth(const std::string& dir, const RenderScene& scene,
                      const calib::CameraModel& camera);

struct GroundTruthFiles {
  SyntheticSvbrdf card;  // its labels, normals and size: LabelAt(), NormalAt() the renderer's rule
  std::vector<std::string> material_names;
  calib::CameraModel camera;
};
// Throws UserError naming the file that is missing or not ground truth.
GroundTruthFiles ReadGroundTruth(const std::string& dir);

}  // namespace acq::sim
