// uwcolmap dense_mesher: a dense surface on the CPU.
#pragma once

#include <string>

#include "colmap_plugins/dense/dense_mesher.h"
#include "common/cli/command.h"

namespace uw {

struct DenseMesherCommandOptions {
  std::string input_path;   // COLMAP model
  std::string image_path;   // its images
  std::string output_path;  // PLY mesh
  // Intermediate files; empty: <output_path>.workspace.
  std::string workspace_path;
  std::string fused_path;  // also the fused oriented points, if given
  DenseMesherOptions mesher;

  void Check() const { mesher.Check(); }
};
Subcommand DenseMesherCommand();

}  // namespace uw
