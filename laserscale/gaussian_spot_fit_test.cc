#include "laserscale/gaussian_spot_fit.h"

#include <gtest/gtest.h>
#include <Eigen/Core>
#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

#include "laserscale/spot_detector.h"
#include "laserscale/spot_detector_testing.h"

namespace uw {
namespace {

TEST(DetectSpots, FitsASyntheticSpotToAHundredthOfAPixel) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  Eigen::Matrix2d shape;
  shape << 3.0, 0.8, 0.8, 2.0;
  const Eigen::Vector2d centre(185.37, 120.71);
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 0;
  const std::vector<DetectedSpot> spots =
      DetectSpots(WithSpot(Flat(320, 240), centre, 120.0, shape, 0.0, 1),
                  cv::Mat(), camera, OneLaser(), options, 1);
  ASSERT_EQ(spots.size(), 1u);
  ASSERT_TRUE(spots[0].detected) << spots[0].problem;
  EXPECT_TRUE(spots[0].stable);
  EXPECT_EQ(spots[0].laser, "L");
  EXPECT_LT((spots[0].pixel - centre).norm(), 0.01);
  // Σc = Σb 2 ln(1.25) / (-2 ln 0.05) (§5.2 step 12); Σb is the spot's
  // shape widened by the low-pass (σ = 1 px).
  const Eigen::Matrix2d expected =
      (shape + Eigen::Matrix2d::Identity()) * 0.44629 / 5.99146;
  EXPECT_LT((spots[0].covariance - expected).norm(), 0.02 * expected.norm())
      << spots[0].covariance;
}

// A spot clipped at 255 over half its width: the clipped pixels bound the
// fit from below instead of being lost, so the centre stays put.
TEST(DetectSpots, SaturatedSpotKeepsItsCentre) {
  const Camera camera = PinholeCamera(320, 240, 400.0);
  Eigen::Matrix2d shape;
  shape << 6.0, -1.0, -1.0, 4.0;
  SpotDetectorOptions options;
  options.monte_carlo_iterations = 0;
  for (const Eigen::Vector2d& centre :
       {Eigen::Vector2d(178.8, 121.3), Eigen::Vector2d(190.21, 118.55)}) {
    const std::vector<DetectedSpot> spots =
        DetectSpots(WithSpot(Flat(320, 240), centre, 900.0, shape, 1.0, 2),
                    cv::Mat(), camera, OneLaser(), options, 1);
    ASSERT_TRUE(spots[0].detected) << spots[0].problem;
    EXPECT_LT((spots[0].pixel - centre).norm(), 0.1) << spots[0].pixel;
  }
}

// A spot sampled without noise on a 21x21 window.
lsd::FitSamples SampleSpot(const lsd::GaussianSpot& spot, double background,
                           double clip) {
  lsd::FitSamples samples;
  const Eigen::Matrix2d precision = spot.covariance.inverse();
  for (int r = 0; r < 21; ++r) {
    for (int c = 0; c < 21; ++c) {
      const Eigen::Vector2d x(c + 0.5, r + 0.5);
      const Eigen::Vector2d d = x - spot.mean;
      const double y =
          background + spot.amplitude * std::exp(-0.5 * d.dot(precision * d));
      samples.xs.push_back(x);
      samples.ys.push_back(std::min(y, clip));
      samples.bounds.push_back(y >= clip ? 1 : 0);
    }
  }
  return samples;
}

lsd::GaussianSpot KnownSpot(double amplitude) {
  lsd::GaussianSpot spot;
  spot.amplitude = amplitude;
  spot.mean = Eigen::Vector2d(10.3, 9.6);
  spot.covariance << 4.0, 1.0, 1.0, 3.0;
  return spot;
}

lsd::GaussianSpot RoughStart() {
  lsd::GaussianSpot start;
  start.amplitude = 50.0;
  start.mean = Eigen::Vector2d(11.0, 9.0);
  start.covariance = 2.0 * Eigen::Matrix2d::Identity();
  return start;
}

TEST(FitSpot, RecoversAKnownSpotFromNoiseFreeSamples) {
  const lsd::GaussianSpot truth = KnownSpot(80.0);
  lsd::GaussianSpot spot;
  ASSERT_TRUE(lsd::FitSpot(SampleSpot(truth, 12.0, 1e9), 10.0, RoughStart(),
                           lsd::PrintGeometry(), &spot, nullptr));
  EXPECT_LT((spot.mean - truth.mean).norm(), 0.005);
  EXPECT_NEAR(spot.amplitude, truth.amplitude, 0.01 * truth.amplitude);
  EXPECT_LT((spot.covariance - truth.covariance).norm(),
            0.02 * truth.covariance.norm())
      << spot.covariance;
}

// Clipped samples bound the model from below: the fit still finds how high
// the spot is.
TEST(FitSpot, ClippedSamplesAreLowerBounds) {
  const lsd::GaussianSpot truth = KnownSpot(200.0);
  const lsd::FitSamples samples = SampleSpot(truth, 12.0, 150.0);
  ASSERT_GT(std::count(samples.bounds.begin(), samples.bounds.end(), 1), 3);
  lsd::GaussianSpot spot;
  ASSERT_TRUE(lsd::FitSpot(samples, 10.0, RoughStart(), lsd::PrintGeometry(),
                           &spot, nullptr));
  EXPECT_LT((spot.mean - truth.mean).norm(), 0.01);
  EXPECT_NEAR(spot.amplitude, truth.amplitude, 0.02 * truth.amplitude);
}

// The model's analytic Jacobian (with the aux's print) against central
// differences; the model evaluates exp in single precision, hence the step
// and the tolerance.
TEST(SpotFit, JacobianMatchesNumericDifferences) {
  lsd::SpotFit<true> fit;
  fit.geometry.offset = Eigen::Vector2d(1.5, -0.5);
  fit.geometry.along = Eigen::Vector2d(0.8, 0.6);
  lsd::SpotFit<true>::Vector theta;
  theta << 5.0, 0.3, 0.05, 0.4, 60.0, 10.0, 11.0, -20.0, 0.7;
  for (const Eigen::Vector2d& x :
       {Eigen::Vector2d(10.5, 11.5), Eigen::Vector2d(12.0, 9.5),
        Eigen::Vector2d(8.5, 12.5), Eigen::Vector2d(13.5, 11.0)}) {
    lsd::SpotFit<true>::Vector jacobian;
    fit.Value(theta, x, &jacobian);
    for (int k = 0; k < lsd::SpotFit<true>::kParams; ++k) {
      const double h = 1e-3 * std::max(1.0, std::abs(theta(k)));
      lsd::SpotFit<true>::Vector plus = theta;
      lsd::SpotFit<true>::Vector minus = theta;
      plus(k) += h;
      minus(k) -= h;
      lsd::SpotFit<true>::Vector ignored;
      const double numeric =
          (fit.Value(plus, x, &ignored) - fit.Value(minus, x, &ignored)) /
          (2.0 * h);
      EXPECT_NEAR(jacobian(k), numeric, 0.01 + 1e-3 * std::abs(numeric))
          << "parameter " << k << " at " << x.transpose();
    }
  }
}

}  // namespace
}  // namespace uw
