#include "laserscale/model_draws.h"

#include <string>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

// Ten points along x, one camera with its focal length refined, and two
// draws: point j moves by (j, 0, 0) mm in the first and (0, j, 0) mm in the
// second; the focal length by +1 and -2 px.
struct Fixture {
  Reconstruction model;
  ModelDraws draws;
  LocalizedImage pose;
};

Fixture MakeFixture() {
  Fixture f;
  Camera camera;
  camera.camera_id = 3;
  camera.model_id = CameraModelId::kSimpleRadial;
  camera.width = 640;
  camera.height = 480;
  camera.params = {500.0, 320.0, 240.0, 0.0};
  f.model.AddCamera(camera);
  CovarianceSamples& samples = f.draws.samples;
  samples.camera_ids = {3};
  samples.camera_param_indices = {{0}};
  samples.camera_deltas.resize(1, 2);
  samples.camera_deltas << 1.0, -2.0;
  samples.log_scale.setZero(2);
  samples.point_deltas.resize(30, 2);
  for (int j = 0; j < 10; ++j) {
    Point3D point;
    point.point3D_id = 100 + j;
    point.xyz = Eigen::Vector3d(j, 0.0, 5.0);
    f.model.AddPoint3D(point);
    samples.point3D_ids.push_back(point.point3D_id);
    samples.point_deltas.block<3, 1>(3 * j, 0) =
        Eigen::Vector3f(1e-3f * j, 0.0f, 0.0f);
    samples.point_deltas.block<3, 1>(3 * j, 1) =
        Eigen::Vector3f(0.0f, 1e-3f * j, 0.0f);
  }
  samples.Index();
  f.draws.gauge = "priors";
  f.pose.name = "L1.png";
  f.pose.camera = camera;
  f.pose.success = true;
  for (const int j : {2, 5}) {
    f.pose.inliers.push_back({Eigen::Vector2d(10.0 * j, 5.0),
                              Eigen::Vector3d(j, 0.0, 5.0),
                              static_cast<point3D_t>(100 + j)});
  }
  return f;
}

TEST(DrawsForImage, CutsTheImagesCameraPointsAndSurface) {
  const Fixture f = MakeFixture();
  // Hits at x = 7.2: the three nearest points are 7, 8 and 6.
  const ImageModelDraws draws = DrawsForImage(
      f.draws, f.model, f.pose, Eigen::Vector3d(7.2, 0.0, 5.0), 3);
  EXPECT_EQ(draws.NumDraws(), 2);
  ASSERT_EQ(draws.param_indices, std::vector<int>{0});
  EXPECT_EQ(draws.camera_deltas(0, 0), 1.0);
  EXPECT_EQ(draws.camera_deltas(0, 1), -2.0);
  ASSERT_EQ(draws.point_deltas.rows(), 6);
  EXPECT_FLOAT_EQ(draws.point_deltas(0, 0), 2e-3f);  // inlier 0 = point 2
  EXPECT_FLOAT_EQ(draws.point_deltas(4, 1), 5e-3f);  // inlier 1 = point 5
  EXPECT_FLOAT_EQ(draws.surface_shifts(0, 0), 7e-3f);
  EXPECT_FLOAT_EQ(draws.surface_shifts(1, 1), 7e-3f);
  EXPECT_NEAR(draws.surface_radius, 1.2, 1e-12);
  EXPECT_EQ(draws.num_points_without_draws, 0);
}

TEST(DrawsForImage, PosesOfAnotherModelAreRefused) {
  const auto expect_error = [](const Fixture& f, const std::string& words) {
    try {
      DrawsForImage(f.draws, f.model, f.pose, Eigen::Vector3d::Zero(), 8);
      ADD_FAILURE() << "no error for " << words;
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos)
          << error.what();
      EXPECT_NE(std::string(error.what()).find("L1.png"), std::string::npos);
    }
  };
  Fixture f = MakeFixture();
  f.pose.inliers[1].point3D_id = kInvalidPoint3DId;
  expect_error(f, "version 1");
  f = MakeFixture();
  f.pose.inliers[0].point_in_world.x() += 0.01;
  expect_error(f, "another model");
  f = MakeFixture();
  f.pose.inliers[0].point3D_id = 999;
  expect_error(f, "another model");
  f = MakeFixture();
  f.pose.camera.params[0] = 501.0;
  expect_error(f, "camera 3");
}

}  // namespace
}  // namespace uw
