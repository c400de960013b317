#include "colmap_plugins/exe/dense_commands.h"

#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"

namespace uw {
namespace {

void AddDenseMesherFlags(CommandLine* cli, DenseMesherCommandOptions* options) {
  cli->Add("--input_path", &options->input_path, "COLMAP model (BIN or TXT)")
      ->required();
  cli->Add("--image_path", &options->image_path, "Folder of the model's images")
      ->required();
  cli->Add("--output_path", &options->output_path, "PLY mesh to write")
      ->required();
  cli->Add("--workspace_path", &options->workspace_path,
           "Folder for intermediate files (fused.ply, colmap's poisson.ply "
           "and log); default: next to --output_path");
  cli->Add("--fused_path", &options->fused_path,
           "Also write the fused oriented points (PLY, as colmap's "
           "stereo_fusion)");
  DenseMesherOptions& mesher = options->mesher;
  cli->Add("--DenseMesher.max_image_size", &mesher.max_image_size,
           "Longest side of the depth maps (px); -1: full size");
  cli->Add("--DenseMesher.voxel_size_factor", &mesher.voxel_size_factor,
           "Fusion voxel in ground sample distances (if --Fusion.voxel_size "
           "is 0)");
  cli->Add("--DenseMesher.num_threads", &mesher.num_threads, "-1: all cores");
  ViewSelectionOptions& views = mesher.view_selection;
  cli->Add("--ViewSelection.num_neighbors", &views.num_neighbors,
           "Source images per depth map");
  cli->Add("--ViewSelection.min_shared_points", &views.min_shared_points,
           "3D points a pair must share");
  cli->Add(
      "--ViewSelection.min_triangulation_angle_deg",
      &views.min_triangulation_angle_deg,
      "Smallest median triangulation angle of a pair's shared points (deg)");
  cli->Add(
      "--ViewSelection.max_triangulation_angle_deg",
      &views.max_triangulation_angle_deg,
      "Largest median triangulation angle of a pair's shared points (deg)");
  cli->Add("--ViewSelection.depth_margin", &views.depth_margin,
           "Widening of the sparse points' depth range (fraction)");
  PlaneSweepOptions& sweep = mesher.plane_sweep;
  cli->Add("--PlaneSweep.window_radius", &sweep.window_radius,
           "NCC window (2r+1)^2 pixels");
  cli->Add("--PlaneSweep.plane_step_px", &sweep.plane_step_px,
           "Largest image motion between planes (px)");
  cli->Add("--PlaneSweep.num_best_sources", &sweep.num_best_sources,
           "Lowest source costs averaged per plane");
  cli->Add("--PlaneSweep.max_cost", &sweep.max_cost,
           "1 - NCC above which a pixel gets no depth");
  cli->Add("--PlaneSweep.min_texture", &sweep.min_texture,
           "Grey-level std-dev (on [0, 1]) below which a pixel gets no "
           "depth");
  FusionOptions& fusion = mesher.fusion;
  cli->Add("--Fusion.min_consistent_views", &fusion.min_consistent_views,
           "Neighbour depth maps that must agree with a depth");
  cli->Add("--Fusion.max_reprojection_error_px",
           &fusion.max_reprojection_error_px,
           "Reprojection error (px) within which a neighbour confirms a depth");
  cli->Add(
      "--Fusion.max_relative_depth_difference",
      &fusion.max_relative_depth_difference,
      "Relative depth difference within which a neighbour confirms a depth");
  cli->Add("--Fusion.max_grazing_angle_deg", &fusion.max_grazing_angle_deg,
           "Largest angle between the normal and the viewing ray (deg)");
  cli->Add("--Fusion.voxel_size", &fusion.voxel_size,
           "Model units; 0: from --DenseMesher.voxel_size_factor");
  cli->Add("--Fusion.min_images_per_voxel", &fusion.min_images_per_voxel,
           "Images that must see a voxel for it to be fused");
  cli->Add("--Poisson.depth", &mesher.poisson.depth,
           "Octree depth; 0: cells of about one voxel");
  cli->Add("--Poisson.point_weight", &mesher.poisson.point_weight,
           "Screening weight: how strongly the surface is pulled through the "
           "points");
  cli->Add("--Poisson.colmap_path", &mesher.poisson.colmap_path,
           "The colmap program");
  TrimmingOptions& trimming = mesher.trimming;
  cli->Add("--Trimming.max_distance", &trimming.max_distance,
           "Model units from the nearest fused point; 0: 2 voxels");
  cli->Add("--Trimming.max_edge_factor", &trimming.max_edge_factor,
           "Drop triangles with an edge longer than this x the median");
  cli->Add("--Trimming.min_component_fraction",
           &trimming.min_component_fraction,
           "Drop pieces smaller than this fraction of the largest");
}

// One line per stage, rewritten in place until the stage is done.
void PrintProgress(const std::string& stage, size_t done, size_t total) {
  fmt::print("\r[dense_mesher] {} {}/{}", stage, done, total);
  if (done == total) fmt::print("\n");
  std::fflush(stdout);
}

void RunDenseMesher(const DenseMesherCommandOptions& options) {
  const std::filesystem::path workspace =
      options.workspace_path.empty() ? options.output_path + ".workspace"
                                     : options.workspace_path;
  const DenseMeshResult result =
      DenseMesh(ReadModel(options.input_path), options.image_path, workspace,
                options.mesher, PrintProgress);
  // Only the model knows its frame: a stock colmap model's is arbitrary in
  // scale and axes (its +z often points into the seabed).
  WritePly(result.mesh, options.output_path,
           "uwcolmap dense_mesher of the model " + options.input_path +
               ": that model's frame and units (metres only if it is metric)");
  if (!options.fused_path.empty()) {
    WriteOrientedPly(result.points, Eigen::Vector3d::Zero(),
                     options.fused_path);
  }
  fmt::print(
      "[dense_mesher] {} of {} images with a depth map, voxel {:.4g}, {} "
      "fused points, Poisson depth {}\n",
      result.num_depth_maps, result.num_images, result.voxel_size,
      result.points.points.size(), result.poisson_depth);
  if (result.poisson_non_finite_vertices > 0) {
    fmt::print(
        "[dense_mesher] colmap's Poisson surface had {} non-finite vertices; "
        "they were dropped with their triangles (small holes there)\n",
        result.poisson_non_finite_vertices);
  }
  std::string times;
  for (const auto& [stage, seconds] : result.seconds) {
    times +=
        fmt::format("{}{} {:.1f} s", times.empty() ? "" : ", ", stage, seconds);
  }
  fmt::print("[dense_mesher] time: {}\n", times);
  fmt::print("[dense_mesher] {} vertices, {} triangles written to {}\n",
             result.mesh.vertices.size(), result.mesh.triangles.size(),
             options.output_path);
}

}  // namespace

Subcommand DenseMesherCommand() {
  return MakeSubcommand<DenseMesherCommandOptions>(
      "dense_mesher",
      "dense surface (PLY) of a model on the CPU: depth maps + Poisson",
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
      AddDenseMesherFlags, RunDenseMesher);
}

}  // namespace uw
