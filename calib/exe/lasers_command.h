// uwcalib lasers: laser lines from board images at many distances
// (lasers.json; docs/uwcalib.md).
#pragma once

#include <string>

#include "calib/board.h"
#include "calib/board_laser_calibration.h"
#include "common/cli/command.h"

namespace uw {

struct CalibLasersOptions {
  std::string images_dir;
  std::string image_list_path;  // only these images; empty: all of them
  CalibrationBoard board;
  std::string cameramodel_path;  // the camera (uwcalib calibrate)
  std::string out;               // lasers.json
  BoardLaserCalibrationOptions lasers;

  void Check() const { lasers.Check(); }
};
Subcommand CalibLasersCommand();

}  // namespace uw
