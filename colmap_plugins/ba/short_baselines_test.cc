#include "colmap_plugins/ba/short_baselines.h"

#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "colmap_plugins/ba/test_scene.h"
#include "common/util/error.h"

namespace uw {
namespace {

TEST(ShortBaselines, TriangulationAngleIsTheWidestPair) {
  Reconstruction model;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimplePinhole;
  camera.width = 100;
  camera.height = 100;
  camera.params = {100.0, 50.0, 50.0};
  model.AddCamera(camera);
  for (const double x : {-0.5, 0.1, 0.5}) {
    Image image;
    image.image_id = static_cast<image_t>(model.Images().size() + 1);
    image.camera_id = 1;
    image.name = "img" + std::to_string(image.image_id);
    image.cam_from_world = test::LookDownFrom({x, 0.0, 3.0}, 0.0);
    model.AddImage(image);
  }
  Point3D point;
  point.point3D_id = 1;
  point.xyz = Eigen::Vector3d::Zero();
  point.track = {{1, 0}, {2, 0}, {3, 0}};
  EXPECT_NEAR(TriangulationAngleDeg(model, point),
              2.0 * std::atan(0.5 / 3.0) * 180.0 / M_PI, 1e-12);
  point.track = {{2, 0}};
  EXPECT_EQ(TriangulationAngleDeg(model, point), 0.0);
}

// One pass at 0.6 m spacing, 3 m above the floor (footprint 3.8 m along
// it): every point is seen over >= 11 deg. Where the vehicle hovered (four
// images within ~0.1 m at station 5) and the stations 2-4 and 6-8 around
// it are missing, the floor under it (x in ~[2.5, 3.5] m) is seen from
// the hover alone: flagged there, nowhere else.
TEST(ShortBaselines, AHoverIsFlaggedAndOnlyThere) {
  test::TestSceneOptions options;
  options.num_lines = 1;
  options.images_per_line = 12;
  options.num_points = 1500;
  const test::TestScene normal = test::MakeTestScene(options);
  EXPECT_TRUE(FindShortBaselines(normal.truth, ShortBaselineOptions())
                  .cell_centres.empty());
  options.missing_images = {{0, 2}, {0, 3}, {0, 4}, {0, 6}, {0, 7}, {0, 8}};
  options.hovers = {{0, 5, 4, 0.03}};
  const test::TestScene hover = test::MakeTestScene(options);
  EXPECT_EQ(hover.truth.Images().size(), 9u);
  const ShortBaselines flagged =
      FindShortBaselines(hover.truth, ShortBaselineOptions());
  std::cout << "[ figures ] hover: " << flagged.cell_centres.size()
            << " cells of " << flagged.cell_size << " m flagged\n";
  ASSERT_GE(flagged.cell_centres.size(), 2u);
  for (size_t k = 0; k < flagged.cell_centres.size(); ++k) {
    const double x = flagged.cell_centres[k].x();
    EXPECT_GT(x, 2.5 - flagged.cell_size) << k;
    EXPECT_LT(x, 3.5 + flagged.cell_size) << k;
    EXPECT_LT(flagged.cell_median_angle_deg[k], 5.0);
  }
  // The default three-line scene has none either.
  EXPECT_TRUE(
      FindShortBaselines(test::MakeTestScene({}).truth, ShortBaselineOptions())
          .cell_centres.empty());
  ShortBaselineOptions bad;
  bad.min_angle_deg = 0.0;
  EXPECT_THROW(bad.Check(), Error);
}

}  // namespace
}  // namespace uw
