#include "colmap_plugins/align/visibility.h"

#include <gtest/gtest.h>

#include "common/mesh/test_meshes.h"
#include "common/util/error.h"

namespace uw {
namespace {

// A 4 x 4 m floor at z = 0 and a 1 x 1 m plate at z = 1 over its centre,
// both facing up, seen by two 200 x 100 px cameras looking straight down
// from z = 3: one over the centre, one 1.5 m to the side.
struct Scene {
  TriangleMesh mesh;
  Reconstruction model;
};

Scene MakeScene(CameraModelId model_id, std::vector<double> params) {
  Scene scene;
  AddGrid({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, 8, 8, &scene.mesh);
  AddGrid({-0.5, -0.5, 1}, {1, 0, 0}, {0, 1, 0}, 2, 2, &scene.mesh);
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = model_id;
  camera.width = 200;
  camera.height = 100;
  camera.params = std::move(params);
  scene.model.AddCamera(camera);
  // Looking down: camera z = world -z, camera x = world x, y = world -y.
  const Eigen::Quaterniond down(
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  for (const double x : {0.0, 1.5}) {
    Image image;
    image.image_id = scene.model.Images().size() + 1;
    image.camera_id = 1;
    image.name = "image" + std::to_string(image.image_id);
    image.cam_from_world.rotation = down;
    image.cam_from_world.translation = -(down * Eigen::Vector3d(x, 0, 3));
    scene.model.AddImage(image);
  }
  return scene;
}

TEST(SurfaceVisibility, InViewIsInFrontAndInsideTheImage) {
  const Scene scene = MakeScene(CameraModelId::kPinhole, {100, 100, 100, 50});
  const RayCaster caster(scene.mesh);
  const SurfaceVisibility visibility(scene.model, caster);
  ASSERT_EQ(visibility.NumViews(), 2u);
  // The point under the first camera projects to the principal point.
  const auto centre = visibility.PixelInView(0, {0, 0, 1});
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR((*centre - Eigen::Vector2d(100, 50)).norm(), 0.0, 1e-12);
  // Half-widths at range 3: 3 m across, 1.5 m along.
  EXPECT_TRUE(visibility.PixelInView(0, {2.9, 0, 0}).has_value());
  EXPECT_FALSE(visibility.PixelInView(0, {3.1, 0, 0}).has_value());
  EXPECT_FALSE(visibility.PixelInView(0, {0, 1.6, 0}).has_value());
  // Behind the camera.
  EXPECT_FALSE(visibility.PixelInView(0, {0, 0, 4}).has_value());
}

TEST(SurfaceVisibility, ObserveLeavesOutOccludedViews) {
  const Scene scene = MakeScene(CameraModelId::kPinhole, {100, 100, 100, 50});
  const RayCaster caster(scene.mesh);
  const SurfaceVisibility visibility(scene.model, caster);
  // On the plate: both cameras see it.
  const auto on_plate = visibility.Observe({0.1, 0.1, 1});
  ASSERT_EQ(on_plate.size(), 2u);
  EXPECT_EQ(on_plate[0].view, 0u);
  EXPECT_EQ(on_plate[1].view, 1u);
  // Under the plate: the first camera's ray crosses z = 1 at x = -0.267,
  // the second's (from x = 1.5) at x = 0.233, both on the plate.
  EXPECT_TRUE(visibility.Observe({-0.4, 0, 0}).empty());
  // Beside the plate: the first camera's ray crosses z = 1 at x = 0.4, on
  // the plate; the second's at x = 0.9, past its edge.
  const auto beside = visibility.Observe({0.6, 0, 0});
  ASSERT_EQ(beside.size(), 1u);
  EXPECT_EQ(beside[0].view, 1u);
  // 0.9 m left of the second camera at range 3: 30 px left of centre.
  EXPECT_NEAR((beside[0].pixel - Eigen::Vector2d(70, 50)).norm(), 0.0, 1e-9);
}

TEST(SurfaceVisibility, FoldedDistortionIsNotInView) {
  // A strong negative k1 folds rays from far outside the field of view back
  // into the image; the round trip through the inverse rejects them.
  const Scene scene =
      MakeScene(CameraModelId::kSimpleRadial, {100, 100, 50, -0.3});
  const RayCaster caster(scene.mesh);
  const SurfaceVisibility visibility(scene.model, caster);
  const Eigen::Vector3d far_out(0, 5.5, -0.0);  // 61 deg off the axis
  const Camera& camera = scene.model.Cameras()[0];
  const Eigen::Vector2d folded =
      camera.ImgFromCam(scene.model.Images()[0].cam_from_world * far_out);
  ASSERT_TRUE(folded.x() >= 0 && folded.x() < 200 && folded.y() >= 0 &&
              folded.y() < 100)
      << folded.transpose();
  EXPECT_FALSE(visibility.PixelInView(0, far_out).has_value());
}

TEST(SurfaceVisibility, UnknownCameraIsAnError) {
  Scene scene = MakeScene(CameraModelId::kPinhole, {100, 100, 100, 50});
  scene.model.Images()[1].camera_id = 7;
  const RayCaster caster(scene.mesh);
  EXPECT_THROW(SurfaceVisibility(scene.model, caster), Error);
}

}  // namespace
}  // namespace uw
