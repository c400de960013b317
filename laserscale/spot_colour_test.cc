#include "laserscale/spot_colour.h"

#include <cmath>

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

TEST(LinearLevel, InvertsTheSrgbCurve) {
  EXPECT_EQ(lsd::LinearLevel(0.0, true), 0.0);
  EXPECT_NEAR(lsd::LinearLevel(255.0, true), 1.0, 1e-12);
  EXPECT_NEAR(lsd::LinearLevel(128.0, true), 0.2158605, 1e-6);
  EXPECT_NEAR(lsd::LinearLevel(-128.0, true), -0.2158605, 1e-6);
  EXPECT_EQ(lsd::LinearLevel(51.0, false), 0.2);
}

// A red spot is red; the lamp's light after the water, blue-green, is not,
// however bright; a spot darker than its background is no laser; a faint
// one whose noise could turn its colour is not refused for its colour.
TEST(IsLaserColour, TellsTheLaserFromTheLamp) {
  const SpotDetectorOptions options;
  const Eigen::Vector3d red(1.0, 0.0, 0.0);
  const Eigen::Vector3d noise = Eigen::Vector3d::Constant(0.001);
  double angle = 0.0;
  EXPECT_TRUE(
      lsd::IsLaserColour({{0.2, 0.01, 0.0}, noise}, red, options, &angle));
  EXPECT_NEAR(angle, std::atan(0.05) * 180.0 / M_PI, 1e-9);
  EXPECT_FALSE(
      lsd::IsLaserColour({{0.02, 0.3, 0.35}, noise}, red, options, &angle));
  EXPECT_GT(angle, 80.0);
  EXPECT_FALSE(
      lsd::IsLaserColour({{-0.2, 0.0, 0.0}, noise}, red, options, &angle));
  // 60 deg off: refused when measured well, kept within its noise (the
  // part across, 0.087, within tan(45 deg) 0.05 + 2 x 0.025).
  const Eigen::Vector3d off(std::cos(M_PI / 3), std::sin(M_PI / 3), 0.0);
  EXPECT_FALSE(lsd::IsLaserColour({0.1 * off, noise}, red, options, &angle));
  EXPECT_TRUE(lsd::IsLaserColour({0.1 * off, Eigen::Vector3d::Constant(0.025)},
                                 red, options, &angle));
  EXPECT_NEAR(angle, 60.0, 1e-9);
  lsd::SpotRgb unmeasured{{0.2, 0.01, 0.0}, noise};
  unmeasured.measured = false;
  EXPECT_FALSE(lsd::IsLaserColour(unmeasured, red, options, &angle));
  SpotDetectorOptions off_test = options;
  off_test.max_colour_angle_deg = 180.0;
  EXPECT_TRUE(
      lsd::IsLaserColour({{0.02, 0.3, 0.35}, noise}, red, off_test, &angle));
}

}  // namespace
}  // namespace uw
