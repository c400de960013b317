#include "laserscale/spot_overlay.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include "common/util/error.h"
#include "laserscale/spot_detector.h"
#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

TEST(DrawSpotOverlay, MarksSpotsAndAddsMagnifiedCrops) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat image = WithSpot(Flat(320, 240), {185.0, 120.0}, 100.0,
                                 Eigen::Matrix2d::Identity() * 3.0, 1.0, 1);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 10;
  std::vector<DetectedSpot> spots =
      DetectSpots(image, cv::Mat(), camera, OneLaser(), options, 1);
  DetectedSpot missing;
  missing.laser = "L9";
  missing.problem = "not detected";
  spots.push_back(missing);
  const cv::Mat overlay = DrawSpotOverlay(image, spots);
  // The image above one row of 192-px tiles.
  ASSERT_EQ(overlay.cols, 320);
  ASSERT_EQ(overlay.rows, 240 + 192);
  EXPECT_GT(cv::norm(overlay(cv::Rect(0, 0, 320, 240)), image, cv::NORM_L1),
            0.0);
  // The tile magnifies the 24x24 pixels around the spot 8 times: unmarked
  // parts are the source pixels, and the marks change others.
  const cv::Mat tile = overlay(cv::Rect(0, 240, 192, 192));
  const int x0 = static_cast<int>(std::floor(spots[0].pixel.x())) - 12;
  const int y0 = static_cast<int>(std::floor(spots[0].pixel.y())) - 12;
  cv::Mat magnified;
  cv::resize(image(cv::Rect(x0, y0, 24, 24)), magnified, cv::Size(192, 192), 0,
             0, cv::INTER_NEAREST);
  EXPECT_EQ(tile.at<cv::Vec3b>(2, 2), magnified.at<cv::Vec3b>(2, 2));
  EXPECT_EQ(tile.at<cv::Vec3b>(189, 189), magnified.at<cv::Vec3b>(189, 189));
  EXPECT_GT(cv::norm(tile, magnified, cv::NORM_L1), 1000.0);
  EXPECT_THROW(DrawSpotOverlay(cv::Mat(), spots), Error);
}

// On a frame of a 27 MP camera the marks are as visible as on a small one:
// 4 px lines 4 times as far out, crops magnified 32 times.
TEST(DrawSpotOverlay, MarksGrowWithTheImage) {
  DetectedSpot spot;
  spot.laser = "L1";
  spot.detected = true;
  spot.stable = true;
  spot.pixel = Eigen::Vector2d(2800.0, 2400.0);
  spot.covariance = Eigen::Matrix2d::Identity() * 0.25;
  const cv::Mat image(4872, 5568, CV_8UC3, cv::Scalar::all(40));
  const cv::Mat overlay = DrawSpotOverlay(image, {spot});
  ASSERT_EQ(overlay.cols, 5568);
  ASSERT_EQ(overlay.rows, 4872 + 24 * 32);
  // The cross's right arm, from 24 to 56 px right of the spot, crossed by a
  // column 40 px out: a line 4 px thick.
  int marked = 0;
  for (int row = 2380; row < 2420; ++row) {
    marked += overlay.at<cv::Vec3b>(row, 2800 + 40) != cv::Vec3b(40, 40, 40);
  }
  EXPECT_GE(marked, 4);
  EXPECT_LE(marked, 6);
}

}  // namespace
}  // namespace uw
