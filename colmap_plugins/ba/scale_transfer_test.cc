#include "colmap_plugins/ba/scale_transfer.h"

#include <string>

#include <gtest/gtest.h>

namespace uw {
namespace {

// Images 1..n along x; a point seen by each listed group of images.
Reconstruction ModelWithTracks(
    int num_images, const std::vector<std::vector<image_t>>& tracks) {
  Reconstruction model;
  for (int i = 1; i <= num_images; ++i) {
    Image image;
    image.image_id = static_cast<image_t>(i);
    image.camera_id = 1;
    image.name = "0" + std::to_string(i) + ".png";
    image.cam_from_world.translation = Eigen::Vector3d(-i, 0, 0);
    model.AddImage(image);
  }
  point3D_t id = 0;
  for (const std::vector<image_t>& images : tracks) {
    Point3D point;
    point.point3D_id = ++id;
    for (const image_t image_id : images) point.track.push_back({image_id, 0});
    model.AddPoint3D(point);
  }
  return model;
}

// The scarp's line end: images 4 and 5 hang on the rest by two-view points
// only, so the images leave the baselines 3-4 and 4-5 free.
TEST(ScaleTransfer, FindsImagesLinkedByTwoViewPointsOnly) {
  const Reconstruction chain = ModelWithTracks(
      5, {{1, 2, 3}, {2, 3}, {3, 4}, {3, 4}, {4, 5}, {4, 5}, {1, 2}});
  EXPECT_EQ(ImagesWithoutScaleTransfer(chain), (std::vector<image_t>{4, 5}));
  const auto fused = ScaleTransferWarning(chain, true);
  ASSERT_TRUE(fused);
  EXPECT_EQ(fused->rfind("2 images share no point that 3 images see with the "
                         "other 3 (e.g. 04.png, 05.png)",
                         0),
            0u)
      << *fused;
  EXPECT_NE(fused->find("navigation alone sets"), std::string::npos);
  EXPECT_NE(ScaleTransferWarning(chain, false)->find("degenerate"),
            std::string::npos);

  // A point seen by 3, 4 and 5 links them: one group.
  const Reconstruction linked =
      ModelWithTracks(5, {{1, 2, 3}, {3, 4, 5}, {3, 4}, {4, 5}});
  EXPECT_TRUE(ImagesWithoutScaleTransfer(linked).empty());
  EXPECT_FALSE(ScaleTransferWarning(linked, true));
}

}  // namespace
}  // namespace uw
