#include "colmap_plugins/nav/camera_mount.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "colmap_plugins/nav/attitude.h"
#include "common/util/error.h"

namespace uw {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

TEST(CameraMount, NamesRoundTripAndUnknownNamesListTheChoices) {
  for (const CameraMount mount : {CameraMount::kDown, CameraMount::kStarboard,
                                  CameraMount::kPort, CameraMount::kForward}) {
    EXPECT_EQ(CameraMountFromName(CameraMountName(mount)), mount);
  }
  try {
    CameraMountFromName("up");
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(),
                 "unknown camera mount 'up' (available: down, starboard, "
                 "port, forward)");
  }
}

// Where each mount looks (camera z) and which way the image's "down"
// (camera y) points, in the vehicle frame (x forward, y left, z up).
TEST(CameraMount, MountsLookWhereTheirNamesSay) {
  const struct {
    CameraMount mount;
    Eigen::Vector3d optical_axis;
    Eigen::Vector3d image_down;
  } cases[] = {
      {CameraMount::kDown, -Eigen::Vector3d::UnitZ(),
       -Eigen::Vector3d::UnitX()},
      {CameraMount::kStarboard, -Eigen::Vector3d::UnitY(),
       -Eigen::Vector3d::UnitZ()},
      {CameraMount::kPort, Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ()},
      {CameraMount::kForward, Eigen::Vector3d::UnitX(),
       -Eigen::Vector3d::UnitZ()},
  };
  for (const auto& test : cases) {
    const Eigen::Matrix3d vehicle_from_cam =
        NominalVehicleFromCamRotation(test.mount);
    EXPECT_LT((vehicle_from_cam.transpose() * vehicle_from_cam -
               Eigen::Matrix3d::Identity())
                  .norm(),
              1e-15);
    EXPECT_DOUBLE_EQ(vehicle_from_cam.determinant(), 1.0);
    EXPECT_EQ(vehicle_from_cam.col(2), test.optical_axis)
        << CameraMountName(test.mount);
    EXPECT_EQ(vehicle_from_cam.col(1), test.image_down)
        << CameraMountName(test.mount);
  }
}

TEST(CameraMount, BoresightTurnsAboutTheCamerasOwnAxes) {
  NavToCameraOptions options;
  options.mount = CameraMount::kStarboard;
  options.lever_arm_m = Eigen::Vector3d(0.6, -0.1, -0.3);
  const Rigid3d nominal = VehicleFromCam(options);
  EXPECT_EQ(nominal.translation, options.lever_arm_m);
  EXPECT_LT((nominal.RotationMatrix() -
             NominalVehicleFromCamRotation(CameraMount::kStarboard))
                .norm(),
            1e-15);
  // Yaw turns about the optical axis: the axis stays, the image turns.
  options.boresight_deg = Eigen::Vector3d(0.0, 0.0, 2.0);
  Rigid3d turned = VehicleFromCam(options);
  EXPECT_LT(
      (turned.RotationMatrix().col(2) - nominal.RotationMatrix().col(2)).norm(),
      1e-15);
  EXPECT_NEAR(turned.rotation.angularDistance(nominal.rotation),
              2.0 * kDegToRad, 1e-12);
  // Roll turns about the camera's x axis (right).
  options.boresight_deg = Eigen::Vector3d(1.5, 0.0, 0.0);
  turned = VehicleFromCam(options);
  EXPECT_LT(
      (turned.RotationMatrix().col(0) - nominal.RotationMatrix().col(0)).norm(),
      1e-15);
  // All three: mount * Rz(yaw) Ry(pitch) Rx(roll).
  options.boresight_deg = Eigen::Vector3d(0.3, -0.5, 0.8);
  EXPECT_LT((VehicleFromCam(options).RotationMatrix() -
             NominalVehicleFromCamRotation(CameraMount::kStarboard) *
                 WorldFromVehicleRotation(options.boresight_deg * kDegToRad))
                .norm(),
            1e-15);
}

TEST(CameraMount, OptionsMustBeFinite) {
  NavToCameraOptions options;
  EXPECT_NO_THROW(options.Check());
  options.lever_arm_m.y() = NAN;
  EXPECT_THROW(options.Check(), Error);
  options = NavToCameraOptions();
  options.boresight_deg.x() = INFINITY;
  EXPECT_THROW(VehicleFromCam(options), Error);
  options = NavToCameraOptions();
  options.time_offset_s = NAN;
  EXPECT_THROW(options.Check(), Error);
}

// As the log's flags are typed: shortest numbers, the mount by name.
TEST(CameraMount, DescriptionNamesEveryPartInOneLine) {
  NavToCameraOptions options;
  EXPECT_EQ(DescribeNavToCamera(options),
            "mount down, lever arm 0,0,0 m, boresight 0,0,0 deg, time offset "
            "0 s");
  options.mount = CameraMount::kStarboard;
  options.lever_arm_m = Eigen::Vector3d(0.6, 0, -0.3);
  options.boresight_deg = Eigen::Vector3d(0.3, -0.5, 0.8);
  options.time_offset_s = 0.25;
  EXPECT_EQ(DescribeNavToCamera(options),
            "mount starboard, lever arm 0.6,0,-0.3 m, boresight 0.3,-0.5,0.8 "
            "deg, time offset 0.25 s");
  // A camera clock 58 days and a quarter second off: every digit.
  options.time_offset_s = 5011200.25;
  EXPECT_NE(DescribeNavToCamera(options).find("time offset 5011200.25 s"),
            std::string::npos);
}

}  // namespace
}  // namespace uw
