// laserscale apply: a COLMAP model, and optionally its mesh, scaled to
// metres by estimate's scale.
#pragma once

#include <string>

#include "common/cli/command.h"

namespace uw {

struct ApplyOptions {
  std::string input_path;           // the model
  std::string scale_path;           // scale.json of estimate
  std::string output_path;          // created; not the input
  std::string output_type = "BIN";  // or TXT
  // Together or neither: the model's mesh (PLY or OBJ) and the PLY to write.
  std::string input_mesh;
  std::string output_mesh;

  // The output type, and outputs that are not the inputs.
  void Check() const;
};
Subcommand ApplyCommand();

}  // namespace uw
