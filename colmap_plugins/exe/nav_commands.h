// uwcolmap pose_prior_importer: camera pose priors from a navigation log
// into a COLMAP database.
#pragma once

#include <string>

#include "colmap_plugins/nav/pose_prior_import.h"
#include "common/cli/command.h"

namespace uw {

struct PosePriorImporterOptions {
  std::string database_path;
  PosePriorImportOptions import;
  // The frame of the log's x,y,z; only "cartesian" (a local metric frame).
  std::string coordinate_system = "cartesian";

  void Check() const;
};
Subcommand PosePriorImporterCommand();

}  // namespace uw
