#include <cstdio>

#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/mesh/mesh.h"
#include "laserscale/exe/commands.h"
#include "laserscale/sparse_surface.h"

namespace uw {

int RunSparseSurface(int argc, char** argv) {
  CLI::App app(
      "A surface for `estimate` from a sparse model's points, when no dense "
      "mesh exists: a heightfield over the points' best-fit plane. It "
      "follows relief only at the scale of the points' spacing (a hit off by "
      "d along a ray at range r biases FUM by about d / r), suits surveys "
      "seen from above, and is no substitute for an MVS mesh on walls or "
      "overhangs.\n\n"
      "Example:\n"
      "  laserscale sparse_surface --input_path sparse/0 --output_path "
      "mesh.ply",
      "laserscale sparse_surface");
  std::string input_path;
  std::string output_path;
  SparseSurfaceOptions options;
  app.add_option("--input_path", input_path, "COLMAP model")->required();
  app.add_option("--output_path", output_path, "PLY mesh to write")->required();
  app.add_option("--grid_spacing", options.grid_spacing,
                 "Model units; <= 0: twice the points' mean spacing")
      ->capture_default_str();
  app.add_option("--min_track_length", options.min_track_length,
                 "Use points seen by at least this many images")
      ->capture_default_str();
  app.add_option("--max_reprojection_error_px",
                 options.max_reprojection_error_px,
                 "Use points with at most this mean reprojection error")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    const TriangleMesh mesh = SparseSurfaceMesh(ReadModel(input_path), options);
    WritePly(mesh, output_path);
    std::printf("[sparse_surface] %zu vertices, %zu triangles written to %s\n",
                mesh.vertices.size(), mesh.triangles.size(),
                output_path.c_str());
  });
}

}  // namespace uw
