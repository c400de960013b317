#include "laserscale/spot_monte_carlo.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include "laserscale/spot_detector.h"
#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

TEST(DetectSpots, MergedSpotIsTheMomentsOfTheIterations) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  Eigen::Matrix2d shape;
  shape << 2.0, 0.5, 0.5, 3.0;
  SpotDetectorOptions options;
  options.noise_sigma = 6.0;
  options.monte_carlo_iterations = 60;
  const cv::Mat image =
      WithSpot(Flat(320, 240), {181.6, 119.2}, 45.0, shape, 2.0, 4);
  const DetectedSpot spot =
      DetectSpots(image, cv::Mat(), camera, OneLaser(), options, 7)[0];
  ASSERT_TRUE(spot.stable) << spot.problem;
  ASSERT_EQ(spot.iterations.size(),
            static_cast<size_t>(std::lround(60 * spot.detection_rate)));
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& [centre, cov] : spot.iterations) mean += centre;
  mean /= spot.iterations.size();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& [centre, cov] : spot.iterations) {
    covariance += cov + (centre - mean) * (centre - mean).transpose();
  }
  covariance /= spot.iterations.size();
  EXPECT_LT((spot.pixel - mean).norm(), 1e-12);
  EXPECT_LT((spot.covariance - covariance).norm(), 1e-12);
  // The noise spreads the centres: the merged covariance exceeds the mean
  // of the iterations' shape covariances.
  Eigen::Matrix2d shape_part = Eigen::Matrix2d::Zero();
  for (const auto& [centre, cov] : spot.iterations) shape_part += cov;
  shape_part /= spot.iterations.size();
  EXPECT_GT(spot.covariance.trace(), shape_part.trace() + 1e-4);
}

TEST(DetectSpots, SameResultForAnySeedDeterministicThreadCount) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  const cv::Mat texture = Texture(320, 240, 9);
  const cv::Mat image = WithSpot(texture, {188.2, 121.9}, 30.0,
                                 Eigen::Matrix2d::Identity() * 2.0, 2.0, 5);
  const cv::Mat aux = WithSpot(texture, {188.2, 121.9}, 0.0,
                               Eigen::Matrix2d::Identity(), 2.0, 6);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 40;
  options.num_threads = 1;
  const DetectedSpot one =
      DetectSpots(image, aux, camera, OneLaser(), options, 11)[0];
  options.num_threads = 3;
  const DetectedSpot three =
      DetectSpots(image, aux, camera, OneLaser(), options, 11)[0];
  ASSERT_TRUE(one.detected);
  EXPECT_EQ(one.pixel, three.pixel);
  EXPECT_EQ(one.covariance, three.covariance);
  EXPECT_EQ(one.detection_rate, three.detection_rate);
  const DetectedSpot other_seed =
      DetectSpots(image, aux, camera, OneLaser(), options, 12)[0];
  EXPECT_NE(one.pixel, other_seed.pixel);
  EXPECT_LT((one.pixel - other_seed.pixel).norm(), 0.2);
}

// A spot at the noise level is found in some iterations only: unstable,
// with the rate in its problem, and not counted as confident.
TEST(DetectSpots, FaintSpotIsUnstable) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 100;
  int unstable = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const cv::Mat image =
        WithSpot(Flat(320, 240), {183.0, 120.5}, 4.5,
                 Eigen::Matrix2d::Identity() * 2.0, 2.0, seed);
    const DetectedSpot spot =
        DetectSpots(image, cv::Mat(), camera, OneLaser(), options, seed)[0];
    EXPECT_TRUE(spot.pixel.allFinite());
    if (spot.detected && !spot.stable) {
      ++unstable;
      EXPECT_LT(spot.detection_rate, options.min_detection_rate);
      EXPECT_EQ(spot.problem.rfind("unstable: detected in ", 0), 0u)
          << spot.problem;
    }
  }
  EXPECT_GE(unstable, 1);
}

TEST(NormalQuantiles, AreAStandardNormalCutAtItsTails) {
  const std::vector<float>& q = lsd::NormalQuantiles();
  ASSERT_EQ(q.size(), 65536u);
  double sum = 0.0;
  double sum2 = 0.0;
  for (size_t i = 0; i < q.size(); ++i) {
    EXPECT_NEAR(q[i], -q[q.size() - 1 - i], 1e-5);
    if (i > 0) {
      EXPECT_LT(q[i - 1], q[i]);
    }
    sum += q[i];
    sum2 += q[i] * q[i];
  }
  EXPECT_NEAR(sum / q.size(), 0.0, 1e-6);
  EXPECT_NEAR(sum2 / q.size(), 1.0, 2e-3);
  // The largest quantile, at 1 - 2^-17.
  EXPECT_NEAR(q.back(), 4.325, 0.001);
}

TEST(WithNoise, IsTheSameForAKeyAndHasItsSigma) {
  const cv::Mat image(100, 100, CV_32FC3, cv::Scalar::all(50.0));
  const cv::Mat a = lsd::WithNoise(image, 3.0, 7);
  EXPECT_EQ(cv::norm(a, lsd::WithNoise(image, 3.0, 7), cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, lsd::WithNoise(image, 3.0, 8), cv::NORM_INF), 0.0);
  cv::Scalar mean;
  cv::Scalar sigma;
  cv::meanStdDev(a.reshape(1) - 50.0, mean, sigma);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(sigma[0], 3.0, 0.05);
}

TEST(NoiseFromImage, EstimatesTheSigmaOfWhiteNoise) {
  lsd::Roi roi;
  roi.main =
      lsd::WithNoise(cv::Mat(80, 80, CV_32FC3, cv::Scalar::all(60.0)), 2.0, 3);
  EXPECT_NEAR(lsd::NoiseFromImage({roi}), 2.0, 0.1);
  EXPECT_EQ(lsd::NoiseFromImage({}), 0.0);
  // Without an aux there is no difference to measure.
  EXPECT_LT(lsd::NoiseFromDifference({roi}, SpotDetectorOptions()), 0.0);
}

TEST(Merge, IsTheMomentsOfTheMixture) {
  lsd::Detection left;
  left.centre = Eigen::Vector2d(0.0, 0.0);
  left.centre_cov = 0.5 * Eigen::Matrix2d::Identity();
  lsd::Detection right = left;
  right.centre = Eigen::Vector2d(2.0, 0.0);
  DetectedSpot spot;
  lsd::Merge({left, right}, &spot);
  EXPECT_EQ(spot.pixel, Eigen::Vector2d(1.0, 0.0));
  Eigen::Matrix2d expected = 0.5 * Eigen::Matrix2d::Identity();
  expected(0, 0) += 1.0;
  EXPECT_LT((spot.covariance - expected).norm(), 1e-12);
}

}  // namespace
}  // namespace uw
