#include "laserscale/laser_poses_io.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace uw {
namespace {

std::vector<LocalizedImage> Example() {
  LocalizedImage good;
  good.name = "L00002.png";
  good.camera.camera_id = 1;
  good.camera.model_id = CameraModelId::kSimpleRadial;
  good.camera.width = 1024;
  good.camera.height = 768;
  good.camera.params = {850.0, 512.0, 384.0, -0.04};
  good.success = true;
  good.cam_from_world.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  good.cam_from_world.translation = Eigen::Vector3d(0.1, -2.0, 3.5);
  good.num_matches = 40;
  good.num_matched_model_images = 3;
  good.rms_error_px = 0.61;
  good.inliers = {{Eigen::Vector2d(10.5, 20.25), Eigen::Vector3d(1, 2, 3), 17},
                  {Eigen::Vector2d(700.0, 300.0), Eigen::Vector3d(-1, 0, 4)}};
  LocalizedImage bad = good;
  bad.name = "L00005.png";
  bad.success = false;
  bad.problem = "3 2D-3D correspondences, fewer than the 15 needed";
  bad.inliers.clear();
  return {good, bad};
}

TEST(LaserPosesJson, RoundTrips) {
  const std::vector<LocalizedImage> images = Example();
  const std::vector<LocalizedImage> read =
      ParseLaserPosesJson(LaserPosesJsonText(images), "poses.json");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].name, "L00002.png");
  EXPECT_TRUE(read[0].success);
  EXPECT_EQ(read[0].camera.params, images[0].camera.params);
  EXPECT_EQ(read[0].camera.model_id, CameraModelId::kSimpleRadial);
  EXPECT_LT((read[0].cam_from_world.translation -
             images[0].cam_from_world.translation)
                .norm(),
            1e-15);
  EXPECT_LT(read[0].cam_from_world.rotation.angularDistance(
                images[0].cam_from_world.rotation),
            1e-12);
  ASSERT_EQ(read[0].inliers.size(), 2u);
  EXPECT_EQ(read[0].inliers[0].pixel, Eigen::Vector2d(10.5, 20.25));
  EXPECT_EQ(read[0].inliers[1].point_in_world, Eigen::Vector3d(-1, 0, 4));
  EXPECT_EQ(read[0].inliers[0].point3D_id, 17u);
  EXPECT_EQ(read[0].inliers[1].point3D_id, kInvalidPoint3DId);
  EXPECT_FALSE(read[1].success);
  EXPECT_EQ(read[1].problem, images[1].problem);
}

// Files of version 1 (inliers without point ids) still read, ids unknown.
TEST(LaserPosesJson, ReadsVersionOne) {
  nlohmann::json json = nlohmann::json::parse(LaserPosesJsonText(Example()));
  json["version"] = 1;
  for (nlohmann::json& row : json["images"][0]["inliers"]) row.erase(5);
  const std::vector<LocalizedImage> read =
      ParseLaserPosesJson(json.dump(), "poses.json");
  ASSERT_EQ(read[0].inliers.size(), 2u);
  EXPECT_EQ(read[0].inliers[0].point_in_world, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(read[0].inliers[0].point3D_id, kInvalidPoint3DId);
  json["version"] = 3;
  EXPECT_THROW(ParseLaserPosesJson(json.dump(), "poses.json"), Error);
}

TEST(LaserPosesJson, RejectsBadInputNamingTheImage) {
  const auto expect_error = [](nlohmann::json json, const std::string& words) {
    try {
      ParseLaserPosesJson(json.dump(), "poses.json");
      ADD_FAILURE() << "no error for " << words;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos)
          << error.what();
    }
  };
  const nlohmann::json good =
      nlohmann::json::parse(LaserPosesJsonText(Example()));
  nlohmann::json json = good;
  json["images"][0]["inliers"][1][2] = "x";
  expect_error(json, "L00002.png");
  json = good;
  json["images"][0]["cam_from_world"]["rotation_wxyz"] = {2.0, 0.0, 0.0, 0.0};
  expect_error(json, "unit quaternion");
  json = good;
  json["images"][0]["camera"]["model"] = "NOPE";
  expect_error(json, "unknown camera model");
  json = good;
  json["images"][0]["camera"]["params"] = {850.0, 512.0};
  expect_error(json, "L00002.png");
  json = good;
  json["images"][0]["surprise"] = 1;
  expect_error(json, "surprise");
  json = good;
  json["format"] = "something-else";
  expect_error(json, "uwmetric-laser-poses");
  json = good;
  json["images"][0]["inliers"][0][5] = -2;
  expect_error(json, "point3D_id");
  json = good;
  json["images"][0]["inliers"][0].erase(5);
  expect_error(json, "point3D_id]");
  json = good;
  json["images"][0].erase("inliers");
  expect_error(json, "inliers");
}

}  // namespace
}  // namespace uw
