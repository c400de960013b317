// laserscale detect: the laser spots of a folder of laser images, with the
// uncertainty of each centre (laserscale/laser_image_detection.h).
#pragma once

#include <string>

#include "common/cli/command.h"
#include "laserscale/laser_image_detection.h"

namespace uw {

struct DetectOptions {
  LaserImageDetectionOptions detection;
  std::string out;           // spots.json to write
  std::string overlays_dir;  // empty: no overlays

  void Check() const { detection.Check(); }
};
Subcommand DetectCommand();

}  // namespace uw
