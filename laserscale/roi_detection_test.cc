#include "laserscale/roi_detection.h"

#include <gtest/gtest.h>

#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

// Without an aux: the nominal detection in ROI coordinates, fitted on the
// laser's (red) channel, and the start of the Monte Carlo's runs.
TEST(PrepareRoi, FindsTheNominalSpot) {
  const Eigen::Vector2d centre(185.37, 120.71);
  const cv::Mat image = WithSpot(Flat(320, 240), centre, 120.0,
                                 2.5 * Eigen::Matrix2d::Identity(), 0.0, 1);
  const SpotDetectorOptions options;
  std::vector<lsd::Roi> rois = lsd::PredictRois(
      image, PinholeCamera(320, 240, 400.0), OneLaser(), options);
  lsd::Roi& roi = rois[0];
  const std::optional<lsd::RoiRun> run =
      lsd::PrepareRoi(image, cv::Mat(), options, &roi);
  ASSERT_TRUE(run.has_value());
  const Eigen::Vector2d corner(roi.rect.x, roi.rect.y);
  EXPECT_LT((run->spot.mean + corner - centre).norm(), 0.02);
  EXPECT_EQ(run->channel, 2);
  EXPECT_EQ(roi.channel, 2);
  ASSERT_TRUE(roi.nominal_spot.has_value());
  EXPECT_FALSE(roi.print.has_value());
  // A run on the same levels starts from the nominal fit and ends there.
  const std::optional<lsd::RoiRun> again = lsd::DetectInRoi(
      roi, roi.main, 1, roi.background, 0.0, roi.channel, options);
  ASSERT_TRUE(again.has_value());
  EXPECT_LT((again->spot.mean - run->spot.mean).norm(), 1e-3);
}

// A "shifted" aux shows the spot a little along the beam: the print, found
// in aux - image, and the spot itself, found in image - aux.
TEST(PrepareRoi, FindsTheAuxsPrintOfTheSpot) {
  const Eigen::Vector2d centre(185.4, 120.3);
  const Eigen::Vector2d printed = centre + Eigen::Vector2d(-7.0, 0.0);
  const cv::Mat texture = Texture(320, 240, 3);
  const Eigen::Matrix2d shape = 2.0 * Eigen::Matrix2d::Identity();
  const cv::Mat image = WithSpot(texture, centre, 80.0, shape, 0.0, 1);
  const cv::Mat aux = WithSpot(texture, printed, 80.0, shape, 0.0, 2);
  const SpotDetectorOptions options;
  std::vector<lsd::Roi> rois = lsd::PredictRois(
      image, PinholeCamera(320, 240, 400.0), OneLaser(), options);
  lsd::Roi& roi = rois[0];
  const std::optional<lsd::RoiRun> run =
      lsd::PrepareRoi(image, aux, options, &roi);
  ASSERT_TRUE(roi.texture_note.empty()) << roi.texture_note;
  const Eigen::Vector2d corner(roi.rect.x, roi.rect.y);
  ASSERT_TRUE(roi.print.has_value());
  EXPECT_LT((roi.print->mean + corner - printed).norm(), 0.3);
  ASSERT_TRUE(run.has_value());
  EXPECT_LT((run->spot.mean + corner - centre).norm(), 0.1);
}

}  // namespace
}  // namespace uw
