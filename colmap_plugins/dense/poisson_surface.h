// Screened Poisson surface reconstruction (Kazhdan & Hoppe 2013) of an
// oriented point cloud by stock `colmap poisson_mesher`, which runs it on
// the CPU with threads. Debian's PCL would bring 414 packages (VTK among
// them) for the same algorithm; colmap is installed anyway.
//
// Poisson closes the surface: far from the points it invents a smooth skirt.
// COLMAP's own trimming (by octree density) is switched off here because it
// removes open sheets such as a seafloor entirely; TrimUnsupported
// (surface_trimming.h) trims by distance to the points instead.
#pragma once

#include <filesystem>
#include <string>

#include "colmap_plugins/dense/depth_fusion.h"
#include "common/mesh/mesh.h"

namespace uw {

struct PoissonOptions {
  // Octree depth: cells of (extent of the points) / 2^depth.
  int depth = 10;
  // Screening weight: how strongly the surface is pulled through the points.
  double point_weight = 1.0;
  int num_threads = -1;  // -1: all cores
  std::string colmap_path = "colmap";

  void Check() const;  // throws uw::Error naming the bad field
};

// Writes the points (recentred, float) to work_dir/fused.ply, runs colmap
// (log: work_dir/poisson_mesher.log) and reads work_dir/poisson.ply back in
// the points' frame. Throws uw::Error with the log's tail if colmap fails.
// Non-finite vertices colmap leaves are dropped with their triangles
// (ReadPlyDroppingNonFinite), counted in *num_dropped_vertices when given.
TriangleMesh PoissonSurface(const OrientedPoints& points,
                            const PoissonOptions& options,
                            const std::filesystem::path& work_dir,
                            size_t* num_dropped_vertices = nullptr);

// Oriented points as binary PLY (x y z nx ny nz as float and a grey
// red green blue, as colmap's stereo_fusion writes them), shifted by -origin;
// atomic.
void WriteOrientedPly(const OrientedPoints& points,
                      const Eigen::Vector3d& origin,
                      const std::filesystem::path& path);

}  // namespace uw
