// uwcalib calibrate: a camera, or a synchronised rig, from corners.vnl with
// mrcal's C library; .cameramodel files and the report (docs/uwcalib.md).
#pragma once

#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/mrcal_calibration.h"
#include "calib/projection_uncertainty.h"
#include "common/cli/command.h"

namespace uw {

struct CalibrateOptions {
  CalibrationBoard board;
  std::string corners_path;  // corners.vnl
  std::string out;           // folder for the outputs (created)
  // A glob of image names per camera of a rig (calib/rig_views.h).
  std::vector<std::string> camera_globs = {"*"};
  // --imagersize WIDTH,HEIGHT writes image_width and image_height.
  MrcalCalibrationOptions calibration;
  ProjectionUncertaintyOptions uncertainty;

  void Check() const {
    calibration.Check();
    uncertainty.Check();
  }
};
Subcommand CalibrateCommand();

}  // namespace uw
