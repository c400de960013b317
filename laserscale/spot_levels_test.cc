#include "laserscale/spot_levels.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace uw {
namespace {

TEST(RobustStats, IsTheMedianAndTheMadSigma) {
  cv::Mat values(1, 101, CV_32F);
  for (int c = 0; c < values.cols; ++c) values.at<float>(0, c) = c;
  cv::Mat mask(values.size(), CV_8U, cv::Scalar(255));
  lsd::RobustLevel level = lsd::RobustStats(values, mask);
  EXPECT_EQ(level.median, 50.0);
  EXPECT_NEAR(level.sigma, lsd::kMadToSigma * 25.0, 1e-9);
  mask(cv::Rect(51, 0, 50, 1)).setTo(0);
  EXPECT_EQ(lsd::RobustStats(values, mask).median, 25.0);
  mask.setTo(0);
  level = lsd::RobustStats(values, mask);
  EXPECT_EQ(level.median, 0.0);
  EXPECT_EQ(level.sigma, 0.0);
}

// The threshold's noise term: white noise after the low-pass has the σ
// that LowPassNoiseGain predicts.
TEST(LowPass, NoiseGainIsThatOfTheKernel) {
  SpotDetectorOptions options;
  cv::Mat noise(300, 300, CV_32F);
  cv::RNG random(5);
  random.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  const cv::Mat blurred = lsd::LowPass(noise, options.lowpass_sigma_px);
  cv::Scalar mean;
  cv::Scalar sigma;
  cv::meanStdDev(blurred(cv::Rect(10, 10, 280, 280)), mean, sigma);
  EXPECT_NEAR(sigma[0], lsd::LowPassNoiseGain(options),
              0.03 * lsd::LowPassNoiseGain(options));
  options.lowpass_sigma_px = 0.0;
  EXPECT_EQ(lsd::LowPassNoiseGain(options), 1.0);
  EXPECT_EQ(lsd::LowPass(noise, 0.0).data, noise.data);
}

TEST(Clipped, IsGrownByTheLowPassReach) {
  cv::Mat levels(21, 21, CV_32FC3, cv::Scalar::all(0.0));
  levels.at<cv::Vec3f>(10, 10)[2] = 255.0f;
  const SpotDetectorOptions options;  // low-pass σ 1 px: reach 3 px
  const cv::Mat red = lsd::Clipped(levels, 2, options);
  EXPECT_EQ(red.at<uint8_t>(10, 13), 255);
  EXPECT_EQ(red.at<uint8_t>(10, 14), 0);
  EXPECT_EQ(red.at<uint8_t>(13, 13), 0);
  EXPECT_EQ(cv::countNonZero(lsd::Clipped(levels, 0, options)), 0);
}

TEST(ValueImage, IsTheLargestChannel) {
  cv::Mat image(1, 2, CV_32FC3);
  image.at<cv::Vec3f>(0, 0) = cv::Vec3f(1.0f, 7.0f, 3.0f);
  image.at<cv::Vec3f>(0, 1) = cv::Vec3f(9.0f, 2.0f, 3.0f);
  const cv::Mat value = lsd::ValueImage(image);
  EXPECT_EQ(value.at<float>(0, 0), 7.0f);
  EXPECT_EQ(value.at<float>(0, 1), 9.0f);
}

}  // namespace
}  // namespace uw
