#include "colmap_plugins/exe/dense_commands.h"

#include <cstdio>
#include <filesystem>
#include <string>

#include "colmap_plugins/dense/dense_mesher.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/mesh/mesh.h"
#include "common/util/error.h"

namespace uw {

int RunDenseMesher(int argc, char** argv) {
  CLI::App app(
      "A dense triangle mesh of a sparse model's scene, on the CPU (stock "
      "colmap's dense stereo needs CUDA): depth maps by plane sweeping each "
      "image against its best neighbours in the model, geometric "
      "consistency, fusion into oriented points, screened Poisson through "
      "`colmap poisson_mesher` and trimming of every triangle no point "
      "supports. The mesh is in the model's units and frame, ready for "
      "`laserscale estimate --mesh`. See docs/uwcolmap.md#dense_mesher.\n\n"
      "Example:\n"
      "  uwcolmap dense_mesher --input_path sparse/0 --image_path images "
      "--output_path dense/mesh.ply",
      "uwcolmap dense_mesher");
  std::string input_path;
  std::string image_path;
  std::string output_path;
  std::string workspace_path;
  std::string fused_path;
  DenseMesherOptions options;
  app.add_option("--input_path", input_path, "COLMAP model (BIN or TXT)")
      ->required();
  app.add_option("--image_path", image_path, "Folder of the model's images")
      ->required();
  app.add_option("--output_path", output_path, "PLY mesh to write")->required();
  app.add_option("--workspace_path", workspace_path,
                 "Folder for intermediate files (fused.ply, colmap's "
                 "poisson.ply and log); default: next to --output_path")
      ->capture_default_str();
  app.add_option("--fused_path", fused_path,
                 "Also write the fused oriented points (PLY, as colmap's "
                 "stereo_fusion)");
  app.add_option("--DenseMesher.max_image_size", options.max_image_size,
                 "Longest side of the depth maps (px); -1: full size")
      ->capture_default_str();
  app.add_option("--DenseMesher.voxel_size_factor", options.voxel_size_factor,
                 "Fusion voxel in ground sample distances (if "
                 "--Fusion.voxel_size is 0)")
      ->capture_default_str();
  app.add_option("--DenseMesher.num_threads", options.num_threads,
                 "-1: all cores")
      ->capture_default_str();
  app.add_option("--ViewSelection.num_neighbors",
                 options.view_selection.num_neighbors,
                 "Source images per depth map")
      ->capture_default_str();
  app.add_option("--ViewSelection.min_shared_points",
                 options.view_selection.min_shared_points,
                 "3D points a pair must share")
      ->capture_default_str();
  app.add_option("--ViewSelection.min_triangulation_angle_deg",
                 options.view_selection.min_triangulation_angle_deg)
      ->capture_default_str();
  app.add_option("--ViewSelection.max_triangulation_angle_deg",
                 options.view_selection.max_triangulation_angle_deg)
      ->capture_default_str();
  app.add_option("--ViewSelection.depth_margin",
                 options.view_selection.depth_margin,
                 "Widening of the sparse points' depth range (fraction)")
      ->capture_default_str();
  app.add_option("--PlaneSweep.window_radius",
                 options.plane_sweep.window_radius,
                 "NCC window (2r+1)^2 pixels")
      ->capture_default_str();
  app.add_option("--PlaneSweep.plane_step_px",
                 options.plane_sweep.plane_step_px,
                 "Largest image motion between planes (px)")
      ->capture_default_str();
  app.add_option("--PlaneSweep.num_best_sources",
                 options.plane_sweep.num_best_sources,
                 "Lowest source costs averaged per plane")
      ->capture_default_str();
  app.add_option("--PlaneSweep.max_cost", options.plane_sweep.max_cost,
                 "1 - NCC above which a pixel gets no depth")
      ->capture_default_str();
  app.add_option("--PlaneSweep.min_texture", options.plane_sweep.min_texture,
                 "Grey-level std-dev (on [0, 1]) below which a pixel gets no "
                 "depth")
      ->capture_default_str();
  app.add_option("--Fusion.min_consistent_views",
                 options.fusion.min_consistent_views,
                 "Neighbour depth maps that must agree with a depth")
      ->capture_default_str();
  app.add_option("--Fusion.max_reprojection_error_px",
                 options.fusion.max_reprojection_error_px)
      ->capture_default_str();
  app.add_option("--Fusion.max_relative_depth_difference",
                 options.fusion.max_relative_depth_difference)
      ->capture_default_str();
  app.add_option("--Fusion.max_grazing_angle_deg",
                 options.fusion.max_grazing_angle_deg)
      ->capture_default_str();
  app.add_option("--Fusion.voxel_size", options.fusion.voxel_size,
                 "Model units; 0: from --DenseMesher.voxel_size_factor")
      ->capture_default_str();
  app.add_option("--Fusion.min_images_per_voxel",
                 options.fusion.min_images_per_voxel)
      ->capture_default_str();
  app.add_option("--Poisson.depth", options.poisson.depth,
                 "Octree depth; 0: cells of about one voxel")
      ->capture_default_str();
  app.add_option("--Poisson.point_weight", options.poisson.point_weight)
      ->capture_default_str();
  app.add_option("--Poisson.colmap_path", options.poisson.colmap_path,
                 "The colmap program")
      ->capture_default_str();
  app.add_option("--Trimming.max_distance", options.trimming.max_distance,
                 "Model units from the nearest fused point; 0: 2 voxels")
      ->capture_default_str();
  app.add_option("--Trimming.max_edge_factor", options.trimming.max_edge_factor,
                 "Drop triangles with an edge longer than this x the median")
      ->capture_default_str();
  app.add_option("--Trimming.min_component_fraction",
                 options.trimming.min_component_fraction,
                 "Drop pieces smaller than this fraction of the largest")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    const std::filesystem::path output(output_path);
    const std::filesystem::path workspace =
        workspace_path.empty()
            ? std::filesystem::path(output_path + ".workspace")
            : std::filesystem::path(workspace_path);
    const Reconstruction model = ReadModel(input_path);
    const DenseMeshResult result =
        DenseMesh(model, image_path, workspace, options,
                  [](const std::string& stage, size_t done, size_t total) {
                    std::printf("\r[dense_mesher] %s %zu/%zu", stage.c_str(),
                                done, total);
                    if (done == total) {
                      std::printf("\n");
                    }
                    std::fflush(stdout);
                  });
    WritePly(result.mesh, output);
    if (!fused_path.empty()) {
      WriteOrientedPly(result.points, Eigen::Vector3d::Zero(), fused_path);
    }
    std::printf(
        "[dense_mesher] %zu of %zu images with a depth map, voxel %.4g, "
        "%zu fused points, Poisson depth %d\n",
        result.num_depth_maps, result.num_images, result.voxel_size,
        result.points.points.size(), result.poisson_depth);
    std::string times;
    for (const auto& [stage, seconds] : result.seconds) {
      char text[64];
      std::snprintf(text, sizeof(text), "%s%s %.1f s",
                    times.empty() ? "" : ", ", stage.c_str(), seconds);
      times += text;
    }
    std::printf("[dense_mesher] time: %s\n", times.c_str());
    std::printf("[dense_mesher] %zu vertices, %zu triangles written to %s\n",
                result.mesh.vertices.size(), result.mesh.triangles.size(),
                output_path.c_str());
  });
}

}  // namespace uw
