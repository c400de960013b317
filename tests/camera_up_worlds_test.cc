// UpFromCameras (colmap_plugins/scene/camera_up.h) on uwsim's surveys of
// every world, floors (seafloor, vent, canyon, the breakwater's slope) and
// a wall (scarp), each model turned as a stock COLMAP model is: the up
// found is the world's, turned with it, to < 5 deg (measured: < 1 deg).
// Where it does not hold: the scarp is surveyed without turning, with the
// camera looking at the wall and its images upright, which rotations
// cannot tell from a down-looking camera over a floor; up is then assumed
// to be minus the optical axis, 90 deg off, and the method says so.
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "colmap_plugins/scene/camera_up.h"
#include "colmap_plugins/scene/model_io.h"
#include "sim/generate.h"
#include "tests/support/process.h"
#include "tests/support/world_plans.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

TEST(UpFromCamerasWorlds, EveryWorldsSurveyGivesItsUp) {
  const fs::path dir = testing::FreshTestDir("uw_camera_up_worlds");
  double worst_deg = 0.0;
  for (const sim::WorldKind world : testing::AllWorlds()) {
    for (const uint64_t seed : {1u, 2u}) {
      const fs::path out = testing::WorldPlan(dir, world, seed);
      Reconstruction model = ReadModel(out / "truth");
      // A stock COLMAP model: the world turned any way.
      const Eigen::Matrix3d model_from_world =
          Eigen::Quaterniond(
              Eigen::Vector4d(0.3 * seed, -0.7, 0.2 * seed, 0.5).normalized())
              .toRotationMatrix();
      for (Image& image : model.Images()) {
        image.cam_from_world.rotation = Eigen::Quaterniond(
            image.cam_from_world.rotation.toRotationMatrix() *
            model_from_world.transpose());
      }
      const std::optional<CameraUp> up = UpFromCameras(model);
      ASSERT_TRUE(up) << out;
      const double error_deg =
          std::acos(std::clamp(up->up_in_model.dot(model_from_world.col(2)),
                               -1.0, 1.0)) *
          180.0 / M_PI;
      std::cout << "[ figures ] " << sim::WorldKindName(world) << " seed "
                << seed << ": " << model.Images().size() << " images, up "
                << error_deg << " deg off (" << up->method << ", agreement "
                << up->agreement << ")\n";
      if (world == sim::WorldKind::kScarp) {
        EXPECT_EQ(up->method.substr(0, 8), "assumed:");
        EXPECT_NEAR(error_deg, 90.0, 5.0);
        continue;
      }
      worst_deg = std::max(worst_deg, error_deg);
      EXPECT_LT(error_deg, 5.0) << out;
    }
  }
  std::cout << "[ figures ] worst but the scarp: " << worst_deg << " deg\n";
}

}  // namespace
}  // namespace uw
