// LEGACY until the commands bind to options (issue 15). The navigation flags
// shared by the uwcolmap commands that read a navigation log
// (pose_prior_importer, bundle_adjuster, lcurve, model_aligner): the log, image
// times, rig, and where the camera sits on the vehicle.
#pragma once

#include <string>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include "colmap_plugins/nav/pose_prior_import.h"

namespace uw {

struct NavFlags {
  std::string nav_path;
  std::string image_times_path;
  std::string rig_config_path;
  std::string mount = "down";
  std::string lever_arm = "0,0,0";
  std::string boresight = "0,0,0";
  double time_offset = 0.0;

  // Adds --nav (required if `nav_required`), --image_times, the rig flag
  // named `rig_flag` (pose_prior_importer: --rig_config; bundle_adjuster:
  // --Rig.config), --mount, --lever_arm, --boresight and --time_offset.
  void Add(CLI::App& app, bool nav_required, const std::string& rig_flag);
  // Parsed and checked; throws uw::Error naming the flag.
  PosePriorImportOptions ToOptions() const;
  // One line: mount, lever arm, boresight, time offset.
  std::string Describe() const;
};

// "x,y,z" as three finite numbers; throws uw::Error naming --flag.
Eigen::Vector3d ParseVector3(const std::string& text, const std::string& flag);

}  // namespace uw
