// laserscale localize: laser images localized against a COLMAP model and
// its database (laserscale/laser_image_localization.h).
#pragma once

#include <string>

#include "common/cli/command.h"
#include "laserscale/localization.h"

namespace uw {

struct LocalizeOptions {
  std::string database_path;
  std::string input_path;  // the model
  // One name per line; empty: every database image the model has not
  // registered.
  std::string image_list_path;
  std::string out;  // poses.json to write
  LocalizationOptions localization;

  void Check() const { localization.Check(); }
};
Subcommand LocalizeCommand();

}  // namespace uw
