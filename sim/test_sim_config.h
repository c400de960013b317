// A small simulation for tests of the generate pipeline: an 8 x 6 m
// seafloor and a 256 x 192 camera, so that a survey renders in a second.
#pragma once

#include "sim/generate.h"

namespace uw::sim {

inline SimConfig SmallSimConfig() {
  SimConfig config;
  config.world_options.seafloor.length_m = 8.0;
  config.world_options.seafloor.width_m = 6.0;
  config.world_options.seafloor.vertex_spacing_m = 0.05;
  config.world_options.seafloor.rocks.count = 5;
  config.camera.width = 256;
  config.camera.height = 192;
  config.camera.params = {212.5, 128.0, 96.0, -0.04};
  config.survey_options.coverage_along = 1.0;
  config.survey_options.coverage_across = 1.0;
  config.render.sensor.supersampling = 1;
  // Laser spots a few pixels wide at this low resolution.
  config.lasers.optics.waist_radius_m = 0.02;
  return config;
}

}  // namespace uw::sim
