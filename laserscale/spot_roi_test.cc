#include "laserscale/spot_roi.h"

#include <gtest/gtest.h>

#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

// The beam runs from x = 200 (1 m) to 166.7 (6 m) along y = 120: its box
// grown by the 24 px margin.
TEST(PredictRois, BoundsTheBeamByTheMargin) {
  const cv::Mat image(240, 320, CV_8UC3, cv::Scalar::all(30));
  const std::vector<lsd::Roi> rois = lsd::PredictRois(
      image, PinholeCamera(320, 240, 400.0), OneLaser(), SpotDetectorOptions());
  ASSERT_EQ(rois.size(), 1u);
  const lsd::Roi& roi = rois[0];
  EXPECT_TRUE(roi.problem.empty());
  EXPECT_EQ(roi.rect, cv::Rect(142, 96, 224 - 142, 48));
  EXPECT_EQ(roi.main.type(), CV_32FC3);
  EXPECT_EQ(roi.main.size(), roi.rect.size());
  EXPECT_EQ(cv::countNonZero(roi.valid), roi.rect.area());
  EXPECT_LT((roi.beams[0].front() - Eigen::Vector2d(58.0, 24.0)).norm(), 1e-9);
  EXPECT_EQ(roi.colour.dominant, 2);
}

TEST(PredictRois, ABeamThatMissesTheImageIsAProblem) {
  LaserSetup setup = OneLaser();
  setup.lasers[0].origin_in_cam = {5.0, 0.0, 0.0};
  const std::vector<lsd::Roi> rois = lsd::PredictRois(
      cv::Mat(240, 320, CV_8UC3, cv::Scalar::all(30)),
      PinholeCamera(320, 240, 400.0), setup, SpotDetectorOptions());
  EXPECT_EQ(rois[0].problem,
            "outside the image (the beam between 1 and 6 m depth does not "
            "project into it)");
  EXPECT_TRUE(rois[0].main.empty());
}

TEST(Crop, ShiftsEverythingIntoTheWindow) {
  std::vector<lsd::Roi> rois = lsd::PredictRois(
      cv::Mat(240, 320, CV_8UC3, cv::Scalar::all(30)),
      PinholeCamera(320, 240, 400.0), OneLaser(), SpotDetectorOptions());
  lsd::Roi& roi = rois[0];
  lsd::GaussianSpot nominal;
  nominal.mean = Eigen::Vector2d(40.0, 20.0);
  roi.nominal_spot = nominal;
  roi.channel = 2;
  for (cv::Mat& clipped : roi.clipped_main) {
    clipped = cv::Mat(roi.rect.size(), CV_8U, cv::Scalar(0));
  }
  const lsd::Roi crop = lsd::Crop(roi, cv::Rect(10, 5, 30, 20));
  EXPECT_EQ(crop.rect, cv::Rect(roi.rect.x + 10, roi.rect.y + 5, 30, 20));
  EXPECT_EQ(crop.main.size(), cv::Size(30, 20));
  EXPECT_EQ(crop.beams[0][0], roi.beams[0][0] - Eigen::Vector2d(10.0, 5.0));
  ASSERT_TRUE(crop.nominal_spot.has_value());
  EXPECT_EQ(crop.nominal_spot->mean, Eigen::Vector2d(30.0, 15.0));
  EXPECT_EQ(crop.channel, 2);
  EXPECT_TRUE(crop.aux.empty());
}

}  // namespace
}  // namespace uw
