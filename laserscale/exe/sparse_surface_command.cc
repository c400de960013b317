#include "laserscale/exe/sparse_surface_command.h"

#include <fmt/format.h>

#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"

namespace uw {
namespace {

void AddSparseSurfaceFlags(CommandLine* cli,
                           SparseSurfaceCommandOptions* options) {
  cli->Add("--input_path", &options->input_path, "COLMAP model")->required();
  cli->Add("--output_path", &options->output_path, "PLY mesh to write")
      ->required();
  SparseSurfaceOptions& surface = options->surface;
  cli->Add("--grid_spacing", &surface.grid_spacing,
           "Model units; <= 0: twice the points' mean spacing");
  cli->Add("--min_track_length", &surface.min_track_length,
           "Use points seen by at least this many images");
  cli->Add("--max_reprojection_error_px", &surface.max_reprojection_error_px,
           "Use points with at most this mean reprojection error");
}

void RunSparseSurface(const SparseSurfaceCommandOptions& options) {
  const TriangleMesh mesh =
      SparseSurfaceMesh(ReadModel(options.input_path), options.surface);
  WritePly(mesh, options.output_path,
           "laserscale sparse_surface of the model " + options.input_path +
               ": that model's frame and units (metres only if it is metric)");
  fmt::print("[sparse_surface] {} vertices, {} triangles written to {}\n",
             mesh.vertices.size(), mesh.triangles.size(),
             options.output_path.c_str());
}

}  // namespace

Subcommand SparseSurfaceCommand() {
  return MakeSubcommand<SparseSurfaceCommandOptions>(
      "sparse_surface",
      "a heightfield mesh from a sparse model, until a dense one exists",
      "A surface for `estimate` from a sparse model's points, when no dense "
      "mesh exists: a heightfield over the points' best-fit plane. It "
      "follows relief only at the scale of the points' spacing (a hit off by "
      "d along a ray at range r biases FUM by about d / r), suits surveys "
      "seen from above, and is no substitute for an MVS mesh on walls or "
      "overhangs.\n\n"
      "Example:\n"
      "  laserscale sparse_surface --input_path sparse/0 --output_path "
      "mesh.ply",
      AddSparseSurfaceFlags, RunSparseSurface);
}

}  // namespace uw
