#include "calib/rig_views.h"

#include <gtest/gtest.h>

#include "common/util/error_testing.h"

namespace uw {
namespace {

std::vector<BoardObservation> Observations(
    const std::vector<std::string>& images) {
  std::vector<BoardObservation> observations;
  for (const std::string& image : images) {
    BoardObservation observation;
    observation.image = image;
    observations.push_back(observation);
  }
  return observations;
}

TEST(FrameOfImage, IsTheLastRunOfDigitsOfTheStem) {
  EXPECT_EQ(FrameOfImage("left01.jpg"), 1);
  EXPECT_EQ(FrameOfImage("cam2/3-cal17.jpg"), 17);
  EXPECT_EQ(FrameOfImage("2-cal0042x.png"), 42);
  ExpectErrorContaining([] { FrameOfImage("left.jpg"); },
                        "left.jpg: a rig's image names need a frame number");
}

TEST(SplitViewsByCamera, OneGlobTakesEveryViewNumberedInFileOrder) {
  const std::vector<RigCameraViews> cameras = SplitViewsByCamera(
      Observations({"b.jpg", "a.jpg", "c.jpg"}), {"*"}, "corners.vnl");
  ASSERT_EQ(cameras.size(), 1u);
  ASSERT_EQ(cameras[0].views.size(), 3u);
  EXPECT_EQ(cameras[0].views[1].image, "a.jpg");
  EXPECT_EQ(cameras[0].frames, (std::vector<int>{0, 1, 2}));
}

TEST(SplitViewsByCamera, TheFirstMatchingGlobWinsFramesFromTheNames) {
  const std::vector<RigCameraViews> cameras = SplitViewsByCamera(
      Observations({"left03.jpg", "right03.jpg", "left04.jpg", "other.jpg"}),
      {"left*", "*03*"}, "corners.vnl");
  ASSERT_EQ(cameras.size(), 2u);
  EXPECT_EQ(cameras[0].frames, (std::vector<int>{3, 4}));
  ASSERT_EQ(cameras[1].views.size(), 1u);
  EXPECT_EQ(cameras[1].views[0].image, "right03.jpg");
  EXPECT_EQ(cameras[1].frames, std::vector<int>{3});
  ExpectErrorContaining(
      [] {
        SplitViewsByCamera(Observations({"left01.jpg"}), {"left*", "zz*"},
                           "all.vnl");
      },
      "all.vnl: no image matches camera 1's glob 'zz*'");
}

}  // namespace
}  // namespace uw
