#include "laserscale/spot_colour.h"

#include <gtest/gtest.h>

namespace uw {
namespace {

TEST(HueDeg, FollowsTheHexcone) {
  EXPECT_EQ(lsd::HueDeg(1.0, 0.0, 0.0), 0.0);
  EXPECT_EQ(lsd::HueDeg(1.0, 1.0, 0.0), 60.0);
  EXPECT_EQ(lsd::HueDeg(0.0, 1.0, 0.0), 120.0);
  EXPECT_EQ(lsd::HueDeg(0.0, 0.0, 1.0), 240.0);
  EXPECT_EQ(lsd::HueDeg(1.0, 0.0, 1.0), 300.0);
  EXPECT_EQ(lsd::HueDeg(0.5, 0.5, 0.5), 0.0);
}

TEST(HueDistanceDeg, WrapsAtRed) {
  EXPECT_EQ(lsd::HueDistanceDeg(350.0, 10.0), 20.0);
  EXPECT_EQ(lsd::HueDistanceDeg(90.0, 270.0), 180.0);
  EXPECT_EQ(lsd::HueDistanceDeg(0.0, 0.0), 0.0);
}

// A red laser is brightest in OpenCV's channel 2 and least seen in 0.
TEST(ColourOf, NamesTheBgrChannels) {
  Laser red;
  red.colour = {1.0, 0.15, 0.1};
  const lsd::LaserColour colour = lsd::ColourOf(red);
  EXPECT_TRUE(colour.chromatic);
  EXPECT_EQ(colour.dominant, 2);
  EXPECT_EQ(colour.weakest, 0);
  EXPECT_NEAR(colour.hue_deg, 60.0 * 0.05 / 0.9, 1e-12);
  Laser white;
  white.colour = {1.0, 0.95, 1.0};
  EXPECT_FALSE(lsd::ColourOf(white).chromatic);
}

}  // namespace
}  // namespace uw
