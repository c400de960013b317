// laserscale sparse_surface: a heightfield mesh from a sparse model, for
// estimate until a dense mesh exists (laserscale/sparse_surface.h).
#pragma once

#include <string>

#include "common/cli/command.h"
#include "laserscale/sparse_surface.h"

namespace uw {

struct SparseSurfaceCommandOptions {
  std::string input_path;   // the model
  std::string output_path;  // PLY mesh to write
  SparseSurfaceOptions surface;

  void Check() const { surface.Check(); }
};
Subcommand SparseSurfaceCommand();

}  // namespace uw
