#include "colmap_plugins/scene/camera_up.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include "colmap_plugins/scene/model_testing.h"

namespace uw {
namespace {

// A model of cameras whose axes in the world are given (columns x, y, z of
// world_from_cam's rotation), then the whole model turned by
// model_from_world, as a stock COLMAP model is.
Reconstruction Cameras(const std::vector<Eigen::Matrix3d>& world_from_cams,
                       const Eigen::Matrix3d& model_from_world) {
  Reconstruction model;
  model.AddCamera(TestPinholeCamera(1, 100, 100.0));
  image_t id = 0;
  for (const Eigen::Matrix3d& world_from_cam : world_from_cams) {
    Image image;
    image.image_id = ++id;
    image.camera_id = 1;
    image.name = std::to_string(id) + ".png";
    image.cam_from_world.rotation =
        Eigen::Quaterniond(model_from_world * world_from_cam).inverse();
    model.AddImage(image);
  }
  return model;
}

Eigen::Matrix3d Rz(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// Down-looking cameras (optical axis -z, turned about it as a survey turns)
// in a model rotated and flipped upside down: up is found as the model's
// image of +z.
TEST(UpFromCameras, DownLookingCamerasGiveUp) {
  Eigen::Matrix3d looking_down;
  looking_down << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // x east, y south, z down
  const Eigen::Matrix3d model_from_world =
      Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, 2, 0.5).normalized())
          .toRotationMatrix();
  std::vector<Eigen::Matrix3d> cams;
  for (int k = 0; k < 12; ++k) {
    const Eigen::Matrix3d tilt =
        Eigen::AngleAxisd(0.1 * std::sin(k), Eigen::Vector3d::UnitX())
            .toRotationMatrix();
    cams.push_back(Rz(0.5 * k) * tilt * looking_down);
  }
  const std::optional<CameraUp> up =
      UpFromCameras(Cameras(cams, model_from_world));
  ASSERT_TRUE(up);
  EXPECT_EQ(up->method, "the axis the cameras turn about");
  EXPECT_LT(up->up_in_model.cross(model_from_world.col(2)).norm(), 0.01);
  EXPECT_GT(up->up_in_model.dot(model_from_world.col(2)), 0.99);
  // The view puts that up on +z and is a rotation (no mirror).
  const Eigen::Matrix3d view = ViewFromModel(up->up_in_model);
  EXPECT_NEAR(view.determinant(), 1.0, 1e-12);
  EXPECT_TRUE((view * up->up_in_model).isApprox(Eigen::Vector3d::UnitZ()));
}

// A wall survey: cameras looking north and turning along the wall, images
// upright (camera +y down): up from the images' down axis.
TEST(UpFromCameras, UprightCamerasAtAWallGiveUp) {
  Eigen::Matrix3d looking_north;
  looking_north << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // x east, y down, z north
  std::vector<Eigen::Matrix3d> cams;
  for (int k = 0; k < 9; ++k)
    cams.push_back(Rz(-1.2 + 0.3 * k) * looking_north);
  const std::optional<CameraUp> up =
      UpFromCameras(Cameras(cams, Eigen::Matrix3d::Identity()));
  ASSERT_TRUE(up);
  EXPECT_EQ(up->method, "the axis the cameras turn about");
  EXPECT_TRUE(up->up_in_model.isApprox(Eigen::Vector3d::UnitZ(), 1e-9));
}

// A single straight pass does not turn: the cameras are taken to look
// down, as at a floor, and the method says it assumed so.
TEST(UpFromCameras, CamerasThatDoNotTurnAreTakenToLookDown) {
  Eigen::Matrix3d looking_down;
  looking_down << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  const Eigen::Matrix3d model_from_world =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const std::optional<CameraUp> up = UpFromCameras(
      Cameras(std::vector<Eigen::Matrix3d>(5, looking_down), model_from_world));
  ASSERT_TRUE(up);
  EXPECT_EQ(up->method.substr(0, 32), "assumed: the cameras look down (");
  EXPECT_TRUE(up->up_in_model.isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
}

// Cameras in every direction (an object turned in front of them) have no
// up to give.
TEST(UpFromCameras, CamerasAllAroundGiveNone) {
  std::vector<Eigen::Matrix3d> cams;
  for (int k = 0; k < 6; ++k) {
    cams.push_back(Eigen::AngleAxisd(M_PI / 3 * k, Eigen::Vector3d::UnitX())
                       .toRotationMatrix());
  }
  EXPECT_FALSE(UpFromCameras(Cameras(cams, Eigen::Matrix3d::Identity())));
  EXPECT_FALSE(UpFromCameras(Reconstruction()));
}

}  // namespace
}  // namespace uw
