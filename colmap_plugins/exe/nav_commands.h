// uwcolmap pose_prior_importer: camera pose priors from a navigation log
// into a COLMAP database; uwcolmap image_times: image_times.csv from the
// images' EXIF or file names.
#pragma once

#include <string>

#include "colmap_plugins/nav/image_time_source.h"
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

struct ImageTimesOptions {
  ImageTimesFromImagesOptions images;
  std::string output_path;

  void Check() const;
};
Subcommand ImageTimesCommand();

}  // namespace uw
