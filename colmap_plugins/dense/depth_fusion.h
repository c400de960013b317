// From per-image depth maps to one oriented point cloud:
// 1. geometric consistency (as COLMAP's fusion): a depth is kept when at
//    least `min_consistent_views` neighbouring depth maps see the same point,
//    i.e. the point projected into the neighbour, lifted with the
//    neighbour's depth and projected back lands within
//    `max_reprojection_error_px` and the depths agree within
//    `max_relative_depth_difference`;
// 2. normals from the kept depths (central differences), facing the camera;
// 3. fusion into voxels: the mean point and normal of every voxel seen by at
//    least `min_images_per_voxel` images.
// The result does not depend on the number of threads: per-image work is
// parallel, the merge is in image order.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "colmap_plugins/dense/pinhole_view.h"

namespace uw {

struct FusionOptions {
  // 1 keeps the seafloor seen by only two images (a survey's outer lines
  // and ends: a fifth of the default survey's surface); a depth still has
  // to be confirmed by another image's independent depth map.
  int min_consistent_views = 1;
  double max_reprojection_error_px = 1.0;
  double max_relative_depth_difference = 0.01;
  // Normals more than this far from the viewing ray are dropped: such
  // depths come from windows smeared along the surface.
  double max_grazing_angle_deg = 80.0;
  // Edge of the fusion voxels (model units); must be set (> 0).
  double voxel_size = 0.0;
  int min_images_per_voxel = 2;

  void Check() const;  // throws uw::Error naming the bad field
};

struct OrientedPoints {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;  // unit, towards the cameras
  std::vector<int> num_images;           // images that saw each point
};

// Depths of `depth_maps[reference]` (CV_32F, 0 = none) that at least
// min_consistent_views of the maps `neighbors` agree with; others set to 0.
cv::Mat ConsistentDepth(size_t reference, const std::vector<size_t>& neighbors,
                        const std::vector<PinholeView>& views,
                        const std::vector<cv::Mat>& depth_maps,
                        const FusionOptions& options);

// Fuses filtered depth maps (one per view) into voxels.
OrientedPoints FuseDepthMaps(const std::vector<PinholeView>& views,
                             const std::vector<cv::Mat>& depth_maps,
                             const FusionOptions& options);

}  // namespace uw
