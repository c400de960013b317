#include "colmap_plugins/dense/depth_fusion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <tbb/task_arena.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
// The seafloor z = kPlaneZ: off the voxel boundaries (multiples of 1, 2 and
// 5 cm), where float rounding would split samples between voxel layers.
constexpr double kPlaneZ = 0.01;

// A camera at `centre_in_world` looking at the world origin, with the
// image's y axis along -y of the world.
Rigid3d CamFromWorldLookingAtOrigin(const Eigen::Vector3d& centre_in_world) {
  const Eigen::Vector3d z = (-centre_in_world).normalized();
  const Eigen::Vector3d x =
      Eigen::Vector3d(0.0, -1.0, 0.0).cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d world_from_cam_rotation;
  world_from_cam_rotation << x, y, z;
  Rigid3d cam_from_world;
  cam_from_world.rotation =
      Eigen::Quaterniond(world_from_cam_rotation.transpose());
  cam_from_world.translation =
      -(world_from_cam_rotation.transpose() * centre_in_world);
  return cam_from_world;
}

// Three views 5 m above the seafloor, 1 m apart, converging on the
// origin.
std::vector<PinholeView> MakeViews() {
  std::vector<PinholeView> views;
  for (const Eigen::Vector3d& centre :
       {Eigen::Vector3d(-1.0, 0.2, 5.0), Eigen::Vector3d(0.0, 0.0, 5.0),
        Eigen::Vector3d(1.0, -0.1, 5.0)}) {
    PinholeView view;
    view.grey = cv::Mat::zeros(kHeight, kWidth, CV_32F);
    view.K << 150.0, 0.0, 79.5, 0.0, 150.0, 59.5, 0.0, 0.0, 1.0;
    view.cam_from_world = CamFromWorldLookingAtOrigin(centre);
    views.push_back(view);
  }
  return views;
}

Eigen::Vector3d Centre(const PinholeView& view) {
  return view.cam_from_world.Inverse().translation;
}

// Exact depths of the plane z = kPlaneZ (ray-plane intersection per
// pixel).
cv::Mat PlaneDepth(const PinholeView& view) {
  cv::Mat depth(kHeight, kWidth, CV_32F);
  const Rigid3d world_from_cam = view.cam_from_world.Inverse();
  const Eigen::Matrix3d rotation = world_from_cam.RotationMatrix();
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      // The ray has z = 1 in the camera, so its parameter is the depth.
      const Eigen::Vector3d ray = rotation * view.CamFromPixel(x, y, 1.0);
      depth.at<float>(y, x) = static_cast<float>(
          (kPlaneZ - world_from_cam.translation.z()) / ray.z());
    }
  }
  return depth;
}

std::vector<cv::Mat> PlaneDepths(const std::vector<PinholeView>& views) {
  std::vector<cv::Mat> depths;
  for (const PinholeView& view : views) {
    depths.push_back(PlaneDepth(view));
  }
  return depths;
}

// How many of `others` see the plane point behind pixel (x, y) of `view`
// inside their image, and whether one of them sees it within `margin` px of
// a rounding boundary of the image (undecidable to the test).
struct Visibility {
  int num_seeing = 0;
  bool ambiguous = false;
};

Visibility SeenBy(const std::vector<PinholeView>& views, size_t view,
                  const cv::Mat& depth, int x, int y,
                  const std::vector<size_t>& others) {
  const Eigen::Vector3d point_in_world =
      views[view].cam_from_world.Inverse() *
      views[view].CamFromPixel(x, y, depth.at<float>(y, x));
  Visibility visibility;
  for (const size_t other : others) {
    const Eigen::Vector2d pixel =
        views[other].PixelFromCam(views[other].cam_from_world * point_in_world);
    const bool inside = pixel.x() > -0.5 && pixel.y() > -0.5 &&
                        pixel.x() < kWidth - 0.5 && pixel.y() < kHeight - 0.5;
    const bool well_inside = pixel.x() > 0.5 && pixel.y() > 0.5 &&
                             pixel.x() < kWidth - 1.5 &&
                             pixel.y() < kHeight - 1.5;
    const bool well_outside = pixel.x() < -1.5 || pixel.y() < -1.5 ||
                              pixel.x() > kWidth + 0.5 ||
                              pixel.y() > kHeight + 0.5;
    visibility.num_seeing += inside ? 1 : 0;
    visibility.ambiguous |= !well_inside && !well_outside;
  }
  return visibility;
}

// The defaults but for the voxel size, which has none.
FusionOptions DefaultFusionOptions() {
  FusionOptions options;
  options.voxel_size = 0.05;
  return options;
}

TEST(ConsistentDepth, KeepsExactDepthsThatEnoughNeighboursSee) {
  const std::vector<PinholeView> views = MakeViews();
  const std::vector<cv::Mat> depths = PlaneDepths(views);
  for (const int min_views : {1, 2}) {
    FusionOptions options = DefaultFusionOptions();
    options.min_consistent_views = min_views;
    const cv::Mat kept = ConsistentDepth(1, {0, 2}, views, depths, options);
    ASSERT_EQ(kept.type(), CV_32F);
    ASSERT_EQ(kept.size(), depths[1].size());
    int num_checked = 0;
    int num_kept = 0;
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        const Visibility visibility = SeenBy(views, 1, depths[1], x, y, {0, 2});
        const float value = kept.at<float>(y, x);
        num_kept += value > 0.0f ? 1 : 0;
        if (visibility.ambiguous) {
          continue;
        }
        ++num_checked;
        if (visibility.num_seeing >= min_views) {
          ASSERT_EQ(value, depths[1].at<float>(y, x))
              << "pixel " << x << ", " << y << " min_views " << min_views;
        } else {
          ASSERT_EQ(value, 0.0f)
              << "pixel " << x << ", " << y << " min_views " << min_views;
        }
      }
    }
    EXPECT_GT(num_checked, 0.9 * kWidth * kHeight);
    // The neighbours' footprints are shifted by 30 px (1 m at 5 m), so a
    // good part but not all of the reference is seen by both.
    EXPECT_GT(num_kept, 0.5 * kWidth * kHeight);
  }
  // Zero consistent views needed: everything is kept.
  FusionOptions options = DefaultFusionOptions();
  options.min_consistent_views = 0;
  EXPECT_EQ(cv::norm(ConsistentDepth(1, {0, 2}, views, depths, options),
                     depths[1], cv::NORM_INF),
            0.0);
}

TEST(ConsistentDepth, RemovesACorruptedBlock) {
  const std::vector<PinholeView> views = MakeViews();
  std::vector<cv::Mat> depths = PlaneDepths(views);
  // 5 % too far (25 cm): beyond max_relative_depth_difference (1 %).
  const cv::Rect block(50, 40, 40, 30);
  depths[0](block) *= 1.05;
  FusionOptions options = DefaultFusionOptions();
  options.min_consistent_views = 2;

  const cv::Mat kept = ConsistentDepth(0, {1, 2}, views, depths, options);
  EXPECT_EQ(cv::countNonZero(kept(block)), 0);
  // Outside the block, as without the corruption.
  const cv::Mat clean =
      ConsistentDepth(0, {1, 2}, views, PlaneDepths(views), options);
  cv::Mat outside_block = cv::Mat::ones(kHeight, kWidth, CV_8U);
  outside_block(block).setTo(0);
  EXPECT_EQ(cv::norm(kept, clean, cv::NORM_INF, outside_block), 0.0);
  EXPECT_GT(cv::countNonZero(clean(block)), 0.9 * block.area());

  // The middle view loses what only the corrupted view and one other
  // confirm, and keeps it when one confirmation is enough.
  const cv::Mat middle = ConsistentDepth(1, {0, 2}, views, depths, options);
  const cv::Mat middle_clean =
      ConsistentDepth(1, {0, 2}, views, PlaneDepths(views), options);
  const int lost = cv::countNonZero(middle_clean) - cv::countNonZero(middle);
  EXPECT_GT(lost, 0.8 * block.area());
  EXPECT_LT(lost, 1.5 * block.area());
  FusionOptions one = options;
  one.min_consistent_views = 1;
  EXPECT_EQ(cv::countNonZero(ConsistentDepth(1, {0, 2}, views, depths, one)),
            cv::countNonZero(
                ConsistentDepth(1, {0, 2}, views, PlaneDepths(views), one)));
}

TEST(ConsistentDepth, SmallDepthErrorsAreTolerated) {
  const std::vector<PinholeView> views = MakeViews();
  std::vector<cv::Mat> depths = PlaneDepths(views);
  const cv::Mat clean =
      ConsistentDepth(0, {1, 2}, views, depths, DefaultFusionOptions());
  // 0.2 % (1 cm): within 1 % in depth and ~0.06 px in reprojection, which
  // only tips the few pixels whose rounding to the neighbour's pixel grid
  // already brought them within 0.06 px of the 1 px limit.
  depths[0] *= 1.002;
  const cv::Mat kept =
      ConsistentDepth(0, {1, 2}, views, depths, DefaultFusionOptions());
  EXPECT_GE(cv::countNonZero(kept), 0.999 * cv::countNonZero(clean));
  EXPECT_GT(cv::countNonZero(clean), 0.8 * kWidth * kHeight);
}

OrientedPoints FuseFilteredPlane(const FusionOptions& options) {
  const std::vector<PinholeView> views = MakeViews();
  std::vector<cv::Mat> depths = PlaneDepths(views);
  depths[0](cv::Rect(50, 40, 40, 30)) *= 1.05;
  std::vector<cv::Mat> filtered;
  for (size_t i = 0; i < views.size(); ++i) {
    std::vector<size_t> neighbors;
    for (size_t j = 0; j < views.size(); ++j) {
      if (j != i) {
        neighbors.push_back(j);
      }
    }
    filtered.push_back(ConsistentDepth(i, neighbors, views, depths, options));
  }
  return FuseDepthMaps(views, filtered, options);
}

TEST(FuseDepthMaps, PointsLieOnThePlaneFacingTheCameras) {
  const std::vector<PinholeView> views = MakeViews();
  const FusionOptions options = DefaultFusionOptions();
  const OrientedPoints fused = FuseFilteredPlane(options);
  ASSERT_EQ(fused.points.size(), fused.normals.size());
  ASSERT_EQ(fused.points.size(), fused.num_images.size());
  // Each view covers about 5.3 x 4 m; their overlap holds some 8000 voxels
  // of 5 cm.
  EXPECT_GT(fused.points.size(), 6000u);
  for (size_t i = 0; i < fused.points.size(); ++i) {
    // Float depths of 5 m are exact to ~3e-7 m.
    ASSERT_NEAR(fused.points[i].z(), kPlaneZ, 2e-6) << i;
    ASSERT_NEAR(fused.normals[i].norm(), 1.0, 1e-12) << i;
    ASSERT_NEAR(fused.normals[i].z(), 1.0, 1e-6) << i;
    for (const PinholeView& view : views) {
      ASSERT_GT(fused.normals[i].dot(Centre(view) - fused.points[i]), 0.0);
    }
    ASSERT_GE(fused.num_images[i], options.min_images_per_voxel);
    ASSERT_LE(fused.num_images[i], 3);
  }
}

TEST(FuseDepthMaps, MinImagesPerVoxelSelectsTheCommonFootprint) {
  FusionOptions options = DefaultFusionOptions();
  options.min_consistent_views = 1;
  options.min_images_per_voxel = 1;
  const OrientedPoints any = FuseFilteredPlane(options);
  options.min_images_per_voxel = 3;
  const OrientedPoints all = FuseFilteredPlane(options);
  EXPECT_GT(all.points.size(), 5000u);
  EXPECT_LT(all.points.size(), any.points.size());
  for (const int num_images : all.num_images) {
    ASSERT_EQ(num_images, 3);
  }
  // Voxels seen by one image only exist when one is enough.
  EXPECT_GT(std::count(any.num_images.begin(), any.num_images.end(), 1), 0);
}

TEST(FuseDepthMaps, GrazingViewsAreDropped) {
  // One view, one image per voxel: every kept point is seen within the
  // maximum angle between its normal and the ray to the camera (plus the
  // 0.3 deg by which the mean of a 2 cm voxel may move the point at 5 m).
  const std::vector<PinholeView> views = {MakeViews()[1]};
  FusionOptions options = DefaultFusionOptions();
  options.voxel_size = 0.02;
  options.min_images_per_voxel = 1;
  options.max_grazing_angle_deg = 15.0;
  const OrientedPoints fused =
      FuseDepthMaps(views, {PlaneDepth(views[0])}, options);
  ASSERT_GT(fused.points.size(), 100u);
  double max_angle_deg = 0.0;
  for (size_t i = 0; i < fused.points.size(); ++i) {
    const Eigen::Vector3d to_camera =
        (Centre(views[0]) - fused.points[i]).normalized();
    max_angle_deg = std::max(
        max_angle_deg,
        std::acos(std::min(1.0, fused.normals[i].dot(to_camera))) * 180 / M_PI);
  }
  EXPECT_LT(max_angle_deg, 15.3);
  EXPECT_GT(max_angle_deg, 14.5);
  // The image's corners are 34 deg off the axis: a wider limit keeps more.
  options.max_grazing_angle_deg = 80.0;
  EXPECT_GT(FuseDepthMaps(views, {PlaneDepth(views[0])}, options).points.size(),
            2 * fused.points.size());
}

TEST(FuseDepthMaps, ResultDoesNotDependOnThreads) {
  const FusionOptions options = DefaultFusionOptions();
  OrientedPoints one_thread;
  OrientedPoints two_threads;
  tbb::task_arena(1).execute([&] { one_thread = FuseFilteredPlane(options); });
  tbb::task_arena(2).execute([&] { two_threads = FuseFilteredPlane(options); });
  ASSERT_EQ(one_thread.points.size(), two_threads.points.size());
  for (size_t i = 0; i < one_thread.points.size(); ++i) {
    ASSERT_EQ(one_thread.points[i], two_threads.points[i]) << i;
    ASSERT_EQ(one_thread.normals[i], two_threads.normals[i]) << i;
    ASSERT_EQ(one_thread.num_images[i], two_threads.num_images[i]) << i;
  }
}

TEST(FuseDepthMaps, InvalidInputsThrow) {
  const std::vector<PinholeView> views = MakeViews();
  ExpectErrorContaining(
      [&] {
        FuseDepthMaps(views, {PlaneDepth(views[0])}, DefaultFusionOptions());
      },
      "3 views but 1 depth maps");
  ExpectErrorContaining(
      [&] { FuseDepthMaps(views, PlaneDepths(views), FusionOptions()); },
      "voxel_size");
}

TEST(FusionOptions, CheckRejectsBadFields) {
  EXPECT_NO_THROW(DefaultFusionOptions().Check());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::pair<std::function<void(FusionOptions*)>, std::string>>
      cases = {
          {[](FusionOptions* o) { o->min_consistent_views = -1; },
           "min_consistent_views"},
          {[](FusionOptions* o) { o->max_reprojection_error_px = 0.0; },
           "max_reprojection_error_px"},
          {[](FusionOptions* o) { o->max_relative_depth_difference = 0.0; },
           "max_relative_depth_difference"},
          {[](FusionOptions* o) { o->max_grazing_angle_deg = 0.0; },
           "max_grazing_angle_deg"},
          {[](FusionOptions* o) { o->max_grazing_angle_deg = 91.0; },
           "max_grazing_angle_deg"},
          {[](FusionOptions* o) { o->voxel_size = 0.0; }, "voxel_size"},
          {[nan](FusionOptions* o) { o->voxel_size = nan; }, "voxel_size"},
          {[inf](FusionOptions* o) { o->voxel_size = inf; }, "voxel_size"},
          {[](FusionOptions* o) { o->min_images_per_voxel = 0; },
           "min_images_per_voxel"},
      };
  for (const auto& [spoil, field] : cases) {
    FusionOptions options = DefaultFusionOptions();
    spoil(&options);
    ExpectErrorContaining([&] { options.Check(); }, field);
  }
}

}  // namespace
}  // namespace uw
