#include "session/sim_instrument.h"

#include "hw/camera.h"

namespace acq {

sim::InstrumentOptions InstrumentOptionsOf(const Plan& plan) {
  sim::InstrumentOptions o;
  o.material_files = plan.sim.materials;
  o.sample = plan.sim.sample;
  o.sample_file = plan.sim.sample_file;
  o.sample_size_mm = plan.sample.width_mm;
  o.sample_height_mm = plan.sample.height_mm;
  o.camera_distance_mm = plan.gantry.camera_distance_mm;
  o.light_distance_mm = plan.gantry.light_distance_mm;
  o.light_intensity = plan.sim.light_intensity;
  o.board = {plan.calibration.board_width_n, plan.calibration.board_height_n,
             plan.calibration.board_spacing_mm};
  o.held_board_poses = plan.calibration.intrinsics_captures;
  o.camera_model_file = plan.sim.camera_model;
  o.image_width = plan.sim.image_width;
  o.image_height = plan.sim.image_height;
  o.pixel_samples = plan.sim.pixel_samples;
  o.camera_filter = plan.sim.camera_filter.value_or(CfaOf(plan.camera.settings.pixel_format));
  o.light_rgb = plan.sim.light_rgb;
  if (const auto& c = plan.sim.chart.covered_mm)
    o.chart_cover =
        Eigen::AlignedBox2d(Eigen::Vector2d((*c)[0], (*c)[1]), Eigen::Vector2d((*c)[2], (*c)[3]));
  o.chart_laid = plan.sim.chart.laid;
  o.chart_turn = plan.sim.chart.turned;
  if (plan.sim.relief) {
    if (!plan.sim.relief->height_map.empty()) {
      o.height_map_file = plan.sim.relief->height_map;
    } else {
      sim::ReliefOptions relief;
      relief.slope_deg = plan.sim.relief->slope_deg;
      relief.fibre_deg = plan.sim.relief->fibre_deg;
      relief.seed = plan.sim.seed;
      o.relief = relief;
    }
  }
  o.firmware.axis = plan.gantry.motion.theta;
  o.firmware.settle_s = plan.gantry.motion.settle_s;
  o.firmware.limits = plan.gantry.motion.constraints;
  o.usb.vendor_id = plan.gantry.usb.vendor_id;
  o.usb.product_id = plan.gantry.usb.product_id;
  o.usb.serial = plan.gantry.usb.serial.empty() ? "SIM-0001" : plan.gantry.usb.serial;
  o.usb.time_scale = plan.sim.time_scale;
  o.seed = plan.sim.seed;
  o.where = plan.path;
  return o;
}

}  // namespace acq
