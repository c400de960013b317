// A dense surface from a sparse COLMAP model and its images, on the CPU:
// view selection from the sparse model (view_selection.h), a depth map per
// image by plane sweeping against its neighbours (plane_sweep.h), geometric
// consistency and fusion into oriented points (depth_fusion.h), screened
// Poisson through stock colmap (poisson_surface.h) and trimming of what no
// point supports (surface_trimming.h). The mesh is in the model's units and
// frame, like the model.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "colmap_plugins/dense/depth_fusion.h"
#include "colmap_plugins/dense/plane_sweep.h"
#include "colmap_plugins/dense/poisson_surface.h"
#include "colmap_plugins/dense/surface_trimming.h"
#include "colmap_plugins/dense/view_selection.h"
#include "colmap_plugins/scene/model.h"
#include "common/mesh/mesh.h"

namespace uw {

struct DenseMesherOptions {
  // Longest side of the depth maps in pixels (images are scaled down to
  // it, never up); -1: full size.
  int max_image_size = 1024;
  ViewSelectionOptions view_selection;
  PlaneSweepOptions plane_sweep;
  // fusion.voxel_size <= 0: `voxel_size_factor` times the median ground
  // sample distance of the depth maps (depth / focal length).
  FusionOptions fusion;
  double voxel_size_factor = 4.0;
  // poisson.depth <= 0 (the default here): the depth whose cells are about
  // one voxel.
  PoissonOptions poisson = [] {
    PoissonOptions automatic;
    automatic.depth = 0;
    return automatic;
  }();
  // trimming.max_distance <= 0: 2 voxels.
  TrimmingOptions trimming;
  int num_threads = -1;  // -1: all cores

  void Check() const;  // throws uw::Error naming the bad field
};

struct DenseMeshResult {
  TriangleMesh mesh;
  OrientedPoints points;
  size_t num_images = 0;
  size_t num_depth_maps = 0;  // images with neighbours and a depth range
  double voxel_size = 0.0;
  int poisson_depth = 0;
  // Non-finite vertices in colmap's Poisson surface, dropped with their
  // triangles before trimming.
  size_t poisson_non_finite_vertices = 0;
  // Wall-clock seconds per stage, by stage name.
  std::map<std::string, double> seconds;
};

// Called as stages progress: (stage, done, total). May be called from
// several threads, never concurrently.
using DenseProgress =
    std::function<void(const std::string& stage, size_t done, size_t total)>;

// Reads image_dir / image.name for every image of the model. work_dir
// receives colmap's input and output (fused.ply, poisson.ply and its log).
// Throws uw::Error naming the image for a missing or unreadable file, and
// when fewer than 2 images get a depth map.
DenseMeshResult DenseMesh(const Reconstruction& model,
                          const std::filesystem::path& image_dir,
                          const std::filesystem::path& work_dir,
                          DenseMesherOptions options,
                          const DenseProgress& progress = nullptr);

}  // namespace uw
