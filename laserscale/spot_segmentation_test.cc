#include "laserscale/spot_segmentation.h"

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include "laserscale/spot_detector.h"
#include "laserscale/spot_detector_testing.h"
#include "laserscale/spot_levels.h"

namespace uw {
namespace {

// The optional hue test: a laser whose set-up colour is green is not found
// in red spots.
TEST(DetectSpots, HueTestRejectsOtherColours) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat image = WithSpot(Flat(320, 240), {185.0, 120.0}, 100.0,
                                 Eigen::Matrix2d::Identity() * 3.0, 1.0, 1);
  SpotDetectorOptions options;
  options.hue_tolerance_deg = 30.0;
  options.min_saturation = 0.3;
  options.monte_carlo_iterations = 10;
  EXPECT_TRUE(
      DetectSpots(image, cv::Mat(), camera, OneLaser(), options, 1)[0].stable);
  LaserSetup green = OneLaser();
  green.lasers[0].colour = {0.1, 1.0, 0.2};
  EXPECT_FALSE(
      DetectSpots(image, cv::Mat(), camera, green, options, 1)[0].detected);
}

TEST(ColourMask, KeepsBrightPixelsAndOpensAwayIsolatedOnes) {
  cv::Mat clean(20, 20, CV_32FC3, cv::Scalar::all(0.0));
  clean(cv::Rect(4, 4, 5, 5)).setTo(cv::Scalar(5.0, 8.0, 50.0));
  clean.at<cv::Vec3f>(15, 15) = cv::Vec3f(5.0f, 8.0f, 50.0f);
  const cv::Mat valid(clean.size(), CV_8U, cv::Scalar(255));
  const lsd::LaserColour red = lsd::ColourOf(OneLaser().lasers[0]);
  const SpotDetectorOptions options;
  const cv::Mat mask = lsd::ColourMask(clean, valid, red, 10.0, options);
  EXPECT_EQ(mask.at<uint8_t>(6, 6), 255);
  EXPECT_EQ(mask.at<uint8_t>(15, 15), 0);
  EXPECT_EQ(cv::countNonZero(lsd::ColourMask(clean, valid, red, 60.0, options)),
            0);
}

// Of the components on the laser's beam the brightest in summed V wins;
// a brighter one off the beam does not, a fainter one on it is a rival.
TEST(BestComponent, TakesTheBrightestOnTheOwnBeam) {
  cv::Mat clean(40, 40, CV_32FC3, cv::Scalar::all(0.0));
  clean(cv::Rect(5, 18, 4, 4)).setTo(cv::Scalar::all(30.0));
  clean(cv::Rect(25, 18, 4, 4)).setTo(cv::Scalar::all(60.0));
  clean(cv::Rect(15, 2, 4, 4)).setTo(cv::Scalar::all(200.0));
  cv::Mat mask;
  cv::compare(lsd::Channel(clean, 0), 10.0, mask, cv::CMP_GT);
  const std::vector<std::vector<Eigen::Vector2d>> beams = {
      {Eigen::Vector2d(0.0, 20.0), Eigen::Vector2d(40.0, 20.0)}};
  SpotDetectorOptions options;
  options.roi_margin_px = 5;
  cv::Rect rivals;
  const cv::Mat best =
      lsd::BestComponent(mask, clean, beams, 0, options, &rivals);
  ASSERT_FALSE(best.empty());
  EXPECT_EQ(best.at<uint8_t>(20, 26), 255);
  EXPECT_EQ(cv::countNonZero(best), 16);
  EXPECT_EQ(rivals, cv::Rect(5, 18, 24, 4));
}

}  // namespace
}  // namespace uw
