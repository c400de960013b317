// uwcalib export: a .cameramodel as a COLMAP camera or OpenCV's YAML
// (docs/uwcalib.md).
#pragma once

#include <cstdint>
#include <string>

#include "common/cli/command.h"

namespace uw {

struct CalibExportOptions {
  std::string cameramodel_path;
  std::string to;  // colmap or opencv-yaml
  // colmap: a COLMAP model folder holding the camera (none: print only),
  // its format and the camera's id.
  std::string output_path;
  std::string output_type = "TXT";  // BIN or TXT
  uint32_t camera_id = 1;
  std::string out;  // opencv-yaml: the file to write

  // --to is colmap or opencv-yaml; colmap: --output_type BIN or TXT;
  // opencv-yaml: --out given.
  void Check() const;
};
Subcommand CalibExportCommand();

}  // namespace uw
