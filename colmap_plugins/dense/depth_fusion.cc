#include "colmap_plugins/dense/depth_fusion.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "common/util/error.h"

namespace uw {

void FusionOptions::Check() const {
  if (min_consistent_views < 0) {
    throw ErrorAt("Fusion.min_consistent_views must be >= 0, got ",
                  min_consistent_views);
  }
  if (!(max_reprojection_error_px > 0.0)) {
    throw ErrorAt("Fusion.max_reprojection_error_px must be > 0, got ",
                  max_reprojection_error_px);
  }
  if (!(max_relative_depth_difference > 0.0)) {
    throw ErrorAt("Fusion.max_relative_depth_difference must be > 0, got ",
                  max_relative_depth_difference);
  }
  if (!(max_grazing_angle_deg > 0.0 && max_grazing_angle_deg <= 90.0)) {
    throw ErrorAt("Fusion.max_grazing_angle_deg must be in (0, 90], got ",
                  max_grazing_angle_deg);
  }
  if (!(voxel_size > 0.0 && std::isfinite(voxel_size))) {
    throw ErrorAt("Fusion.voxel_size must be > 0, got ", voxel_size);
  }
  if (min_images_per_voxel < 1) {
    throw ErrorAt("Fusion.min_images_per_voxel must be >= 1, got ",
                  min_images_per_voxel);
  }
}

cv::Mat ConsistentDepth(size_t reference, const std::vector<size_t>& neighbors,
                        const std::vector<PinholeView>& views,
                        const std::vector<cv::Mat>& depth_maps,
                        const FusionOptions& options) {
  options.Check();
  if (views.size() != depth_maps.size() || reference >= views.size()) {
    throw ErrorAt("ConsistentDepth: ", views.size(), " views, ",
                  depth_maps.size(), " depth maps, reference ", reference);
  }
  for (const size_t j : neighbors) {
    if (j >= views.size() || depth_maps[j].size() != views[j].grey.size() ||
        depth_maps[j].type() != CV_32F) {
      throw ErrorAt("ConsistentDepth: neighbour ", j,
                    " has no depth map of its view's size");
    }
  }
  const PinholeView& ref = views[reference];
  const cv::Mat& ref_depth = depth_maps[reference];
  cv::Mat kept = cv::Mat::zeros(ref_depth.size(), CV_32F);
  struct Neighbor {
    const PinholeView* view;
    const cv::Mat* depth;
    Rigid3d cam_from_ref;
    Rigid3d ref_from_cam;
  };
  std::vector<Neighbor> others;
  const Rigid3d world_from_ref = ref.cam_from_world.Inverse();
  for (const size_t j : neighbors) {
    Neighbor n;
    n.view = &views[j];
    n.depth = &depth_maps[j];
    const Eigen::Matrix3d R = views[j].cam_from_world.RotationMatrix() *
                              world_from_ref.RotationMatrix();
    n.cam_from_ref.rotation = Eigen::Quaterniond(R);
    n.cam_from_ref.translation =
        views[j].cam_from_world * world_from_ref.translation;
    n.ref_from_cam = n.cam_from_ref.Inverse();
    others.push_back(n);
  }
  const double max_error_sq =
      options.max_reprojection_error_px * options.max_reprojection_error_px;
  for (int y = 0; y < ref_depth.rows; ++y) {
    for (int x = 0; x < ref_depth.cols; ++x) {
      const float depth = ref_depth.at<float>(y, x);
      if (!(depth > 0.0f)) {
        continue;
      }
      const Eigen::Vector3d point_in_ref = ref.CamFromPixel(x, y, depth);
      int consistent = 0;
      for (const Neighbor& n : others) {
        const Eigen::Vector3d point_in_cam = n.cam_from_ref * point_in_ref;
        if (point_in_cam.z() <= 0.0) {
          continue;
        }
        const Eigen::Vector2d pixel = n.view->PixelFromCam(point_in_cam);
        const int u = static_cast<int>(std::lround(pixel.x()));
        const int v = static_cast<int>(std::lround(pixel.y()));
        if (u < 0 || v < 0 || u >= n.depth->cols || v >= n.depth->rows) {
          continue;
        }
        const double other_depth = n.depth->at<float>(v, u);
        if (!(other_depth > 0.0) ||
            std::abs(other_depth - point_in_cam.z()) >
                options.max_relative_depth_difference * point_in_cam.z()) {
          continue;
        }
        const Eigen::Vector3d back =
            n.ref_from_cam * n.view->CamFromPixel(u, v, other_depth);
        if (back.z() <= 0.0) {
          continue;
        }
        if ((ref.PixelFromCam(back) - Eigen::Vector2d(x, y)).squaredNorm() <=
            max_error_sq) {
          ++consistent;
        }
      }
      if (consistent >= options.min_consistent_views) {
        kept.at<float>(y, x) = depth;
      }
    }
  }
  return kept;
}

namespace {

struct OrientedSample {
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
};

// Camera-facing points with normals of one filtered depth map, in world
// coordinates.
std::vector<OrientedSample> OrientedSamples(const PinholeView& view,
                                            const cv::Mat& depth,
                                            double max_grazing_angle_deg) {
  // Central differences over +-2 pixels: smoother than +-1 at the same
  // resolution of relief.
  constexpr int kStep = 2;
  const double min_cos = std::cos(max_grazing_angle_deg * M_PI / 180.0);
  const Rigid3d world_from_cam = view.cam_from_world.Inverse();
  const Eigen::Matrix3d world_R = world_from_cam.RotationMatrix();
  std::vector<OrientedSample> samples;
  auto point_at = [&](int x, int y, Eigen::Vector3d* point) {
    const float d = depth.at<float>(y, x);
    if (!(d > 0.0f)) {
      return false;
    }
    *point = view.CamFromPixel(x, y, d);
    return true;
  };
  for (int y = kStep; y + kStep < depth.rows; ++y) {
    for (int x = kStep; x + kStep < depth.cols; ++x) {
      Eigen::Vector3d center, left, right, up, down;
      if (!point_at(x, y, &center) || !point_at(x - kStep, y, &left) ||
          !point_at(x + kStep, y, &right) || !point_at(x, y - kStep, &up) ||
          !point_at(x, y + kStep, &down)) {
        continue;
      }
      Eigen::Vector3d normal = (right - left).cross(down - up);
      if (normal.norm() == 0.0) {
        continue;
      }
      normal.normalize();
      const Eigen::Vector3d to_camera = -center.normalized();
      double facing = normal.dot(to_camera);
      if (facing < 0.0) {
        normal = -normal;
        facing = -facing;
      }
      if (facing < min_cos) {
        continue;
      }
      samples.push_back({world_from_cam * center, world_R * normal});
    }
  }
  return samples;
}

struct VoxelKeyHash {
  size_t operator()(const Eigen::Matrix<int64_t, 3, 1>& key) const {
    return static_cast<size_t>(key.x() * 73856093LL ^ key.y() * 19349663LL ^
                               key.z() * 83492791LL);
  }
};

}  // namespace

OrientedPoints FuseDepthMaps(const std::vector<PinholeView>& views,
                             const std::vector<cv::Mat>& depth_maps,
                             const FusionOptions& options) {
  options.Check();
  if (views.size() != depth_maps.size()) {
    throw ErrorAt("FuseDepthMaps: ", views.size(), " views but ",
                  depth_maps.size(), " depth maps");
  }
  std::vector<std::vector<OrientedSample>> samples(views.size());
  tbb::parallel_for(size_t{0}, views.size(), [&](size_t i) {
    samples[i] =
        OrientedSamples(views[i], depth_maps[i], options.max_grazing_angle_deg);
  });

  struct Voxel {
    Eigen::Vector3d point_sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    int num_samples = 0;
    int num_images = 0;
    int last_image = -1;
  };
  std::vector<Voxel> voxels;
  std::unordered_map<Eigen::Matrix<int64_t, 3, 1>, size_t, VoxelKeyHash> index;
  for (size_t i = 0; i < samples.size(); ++i) {
    for (const OrientedSample& sample : samples[i]) {
      const Eigen::Matrix<int64_t, 3, 1> key =
          (sample.point / options.voxel_size)
              .array()
              .floor()
              .cast<int64_t>()
              .matrix();
      const auto [found, inserted] = index.try_emplace(key, voxels.size());
      if (inserted) {
        voxels.emplace_back();
      }
      Voxel& voxel = voxels[found->second];
      voxel.point_sum += sample.point;
      voxel.normal_sum += sample.normal;
      ++voxel.num_samples;
      if (voxel.last_image != static_cast<int>(i)) {
        voxel.last_image = static_cast<int>(i);
        ++voxel.num_images;
      }
    }
    samples[i].clear();
    samples[i].shrink_to_fit();
  }
  OrientedPoints fused;
  for (const Voxel& voxel : voxels) {
    if (voxel.num_images < options.min_images_per_voxel ||
        voxel.normal_sum.norm() == 0.0) {
      continue;
    }
    fused.points.push_back(voxel.point_sum / voxel.num_samples);
    fused.normals.push_back(voxel.normal_sum.normalized());
    fused.num_images.push_back(voxel.num_images);
  }
  return fused;
}

}  // namespace uw
