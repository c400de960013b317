#include "laserscale/image_scale_estimation.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "common/util/error.h"
#include "common/util/error_testing.h"

namespace uw {
namespace {

LaserSetup TwoLasers(const std::string& name) {
  LaserSetup setup;
  setup.name = name;
  setup.lasers.resize(2);
  setup.lasers[0].name = "L1";
  setup.lasers[1].name = "L2";
  return setup;
}

DetectedSpot Spot(const std::string& laser, bool stable, double x) {
  DetectedSpot spot;
  spot.laser = laser;
  spot.detected = true;
  spot.stable = stable;
  spot.pixel = {x, 2.0 * x};
  spot.covariance = x * Eigen::Matrix2d::Identity();
  return spot;
}

TEST(FindLaserSetup, ByNameOrTheOnlyOne) {
  const std::vector<LaserSetup> one = {TwoLasers("A")};
  const std::vector<LaserSetup> two = {TwoLasers("A"), TwoLasers("B")};
  EXPECT_EQ(FindLaserSetup(one, "", "lasers.json").name, "A");
  EXPECT_EQ(FindLaserSetup(two, "B", "lasers.json").name, "B");
  EXPECT_EQ(ErrorOf([&] { FindLaserSetup(two, "", "lasers.json"); }),
            "lasers.json has 2 set-ups; choose one with --setup");
  EXPECT_EQ(ErrorOf([&] { FindLaserSetup(one, "C", "lasers.json"); }),
            "lasers.json: no set-up named 'C'");
}

TEST(LaserImageFromDetections, TakesEachLasersStableSpotInSetUpOrder) {
  LocalizedImage pose;
  pose.name = "L1.png";
  pose.success = true;
  pose.rms_error_px = 0.7;
  pose.cam_from_world.translation = {1.0, 2.0, 3.0};
  pose.inliers.resize(3);
  ImageSpots spots;
  spots.name = "L1.png";
  spots.spots = {Spot("L2", true, 10.0), Spot("L1", false, 20.0),
                 Spot("other", true, 30.0)};
  const LaserImage image =
      LaserImageFromDetections(pose, spots, TwoLasers("A"));
  EXPECT_EQ(image.name, "L1.png");
  EXPECT_EQ(image.matches.size(), 3u);
  EXPECT_EQ(image.feature_sigma_px, 0.7);
  EXPECT_EQ(image.cam_from_world.translation, pose.cam_from_world.translation);
  ASSERT_EQ(image.spots.size(), 2u);
  EXPECT_FALSE(image.spots[0]);  // L1's spot is not stable
  ASSERT_TRUE(image.spots[1]);
  EXPECT_EQ(image.spots[1]->pixel, Eigen::Vector2d(10.0, 20.0));
  EXPECT_EQ(image.spots[1]->covariance, 10.0 * Eigen::Matrix2d::Identity());
}

TEST(EstimateLaserImages, AnImageNotLocalizedOrWithoutSpotsGetsItsProblem) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 5}, {1, 0, 5}, {0, 1, 5}};
  mesh.triangles = {{0, 1, 2}};
  const RayCaster caster(mesh);
  std::vector<LocalizedImage> poses(2);
  poses[0].name = "a.png";
  poses[0].problem = "12 inliers";
  poses[1].name = "b.png";
  poses[1].success = true;
  ImageSpots spots;
  spots.name = "c.png";
  ImageScaleEstimationOptions options;
  options.spots_path = "spots.json";
  std::vector<size_t> seen;
  const std::vector<ImageEstimate> estimates = EstimateLaserImages(
      poses, {spots}, TwoLasers("A"), caster, options,
      [&](size_t i, size_t count, const ImageEstimate& estimate) {
        EXPECT_EQ(count, 2u);
        EXPECT_EQ(estimate.name, poses[i].name);
        seen.push_back(i);
      });
  EXPECT_EQ(seen, (std::vector<size_t>{0, 1}));
  ASSERT_EQ(estimates.size(), 2u);
  EXPECT_EQ(estimates[0].problem, "not localized: 12 inliers");
  EXPECT_EQ(estimates[1].problem, "no entry in spots.json");
  EXPECT_FALSE(estimates[0].result);
  EXPECT_FALSE(estimates[1].result);
}

}  // namespace
}  // namespace uw
