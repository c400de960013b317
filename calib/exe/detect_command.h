// uwcalib detect: a board's corners in every image, as mrcal's corners.vnl
// (docs/uwcalib.md).
#pragma once

#include <string>

#include "calib/board.h"
#include "common/cli/command.h"

namespace uw {

struct CalibDetectOptions {
  CalibrationBoard board;
  std::string images_dir;
  std::string image_list_path;  // only these images; empty: all of them
  std::string out;              // corners.vnl
  int num_threads = 0;          // <= 0: all

  void Check() const {}
};
Subcommand CalibDetectCommand();

}  // namespace uw
