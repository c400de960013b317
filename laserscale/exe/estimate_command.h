// laserscale estimate: the model's scale with its 95 % interval from its
// localized laser images, and the report folder.
#pragma once

#include <string>

#include "common/cli/command.h"
#include "laserscale/image_scale_estimation.h"
#include "laserscale/scale_report.h"

namespace uw {

struct EstimateOptions {
  std::string mesh_path;    // the model's surface, model units and frame
  std::string poses_path;   // poses.json of localize
  std::string lasers_path;  // lasers.json
  std::string setup_name;   // empty: the only set-up
  // The model's covariance folder (covariance_estimator with
  // --Covariance.samples) and the model itself; empty: the model is taken
  // as exact.
  std::string covariance_path;
  std::string input_path;
  // Its spots_path (--spots), overlays_dir and report_dir (--out).
  ImageScaleEstimationOptions images;
  CombineOptions combine;

  void Check() const;
};
Subcommand EstimateCommand();

}  // namespace uw
