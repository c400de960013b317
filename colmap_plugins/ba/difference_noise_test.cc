#include "colmap_plugins/ba/difference_noise.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

// Three dives of 200 samples at irregular times, white noise of `sigma`
// times the stated 5 cm (z stated 2 cm), plus a smooth departure of
// `bend_m` (a bowl over each dive and a per-dive offset) that no
// difference should see.
std::vector<TimedResidual> Residuals(double sigma, double bend_m,
                                     unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> gap(0.5, 1.5);
  std::vector<TimedResidual> residuals;
  for (int dive = 1; dive <= 3; ++dive) {
    double time = 1000.0 * dive;
    for (int i = 0; i < 200; ++i) {
      time += gap(rng);
      const double u = (i - 100.0) / 100.0;
      TimedResidual r;
      r.dive = dive;
      r.time_s = time;
      r.covariance =
          Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
      r.residual = Eigen::Vector3d(0.05 * normal(rng), 0.05 * normal(rng),
                                   0.02 * normal(rng)) *
                       sigma +
                   bend_m * Eigen::Vector3d(u * u, 0.5 * u, 0.3 * u * u) +
                   Eigen::Vector3d(0.1 * dive, -0.2 * dive, 0.0);
      residuals.push_back(r);
    }
  }
  return residuals;
}

TEST(DifferenceNoise, FollowsTheWhiteNoiseAndNotASmoothDeparture) {
  for (const double sigma : {0.5, 1.0, 3.0}) {
    for (const double bend_m : {0.0, 2.0}) {
      const auto residuals = Residuals(sigma, bend_m, 7);
      for (const int lag : {1, 2}) {
        const auto noise = EstimateDifferenceNoise(residuals, lag);
        ASSERT_TRUE(noise);
        EXPECT_EQ(noise->num_differences, 3 * (200 - 2 * lag));
        // 600 differences: the scale to 2.3 % (RelativeSigma; neighbouring
        // differences correlate, so more than the 1.7 % of independent
        // ones).
        EXPECT_NEAR(noise->scale, sigma, 0.1 * sigma)
            << "sigma " << sigma << " bend " << bend_m << " lag " << lag;
      }
    }
  }
}

TEST(DifferenceNoise, TheOrderIsTimeNotTheInputs) {
  auto residuals = Residuals(1.0, 2.0, 11);
  const double in_order = EstimateDifferenceNoise(residuals, 1)->scale;
  std::reverse(residuals.begin(), residuals.end());
  std::swap(residuals[3], residuals[400]);
  EXPECT_DOUBLE_EQ(EstimateDifferenceNoise(residuals, 1)->scale, in_order);
}

// A log interpolated halfway between fixes: every other sample is the mean
// of its neighbours' errors, which differences over 1 sample barely see
// (0.43 of the noise where it is white, by the algebra of the means),
// while those over 2 see more (0.76). The ratio is what tells it.
TEST(DifferenceNoise, InterpolatedLogsDifferByLag) {
  auto residuals = Residuals(1.0, 0.0, 3);
  for (size_t i = 1; i + 1 < residuals.size(); i += 2) {
    if (residuals[i - 1].dive != residuals[i + 1].dive) continue;
    residuals[i].residual =
        0.5 * (residuals[i - 1].residual + residuals[i + 1].residual);
  }
  const double lag1 = EstimateDifferenceNoise(residuals, 1)->scale;
  const double lag2 = EstimateDifferenceNoise(residuals, 2)->scale;
  EXPECT_NEAR(lag1, 0.43, 0.06);
  EXPECT_NEAR(lag2, 0.76, 0.08);
  EXPECT_GT(lag2 / lag1, 1.5);
}

// The images of a rig share their navigation sample: one per time counts.
TEST(DifferenceNoise, OneSamplePerTime) {
  auto residuals = Residuals(1.0, 0.0, 5);
  const auto single = EstimateDifferenceNoise(residuals, 1);
  const auto copies = residuals;
  residuals.insert(residuals.end(), copies.begin(), copies.end());
  const auto doubled = EstimateDifferenceNoise(residuals, 1);
  ASSERT_TRUE(single && doubled);
  EXPECT_EQ(doubled->num_differences, single->num_differences);
  EXPECT_DOUBLE_EQ(doubled->scale, single->scale);
}

TEST(DifferenceNoise, TooFewOrABadLag) {
  auto residuals = Residuals(1.0, 0.0, 1);
  residuals.resize(11);  // one dive: 9 differences at lag 1
  EXPECT_FALSE(EstimateDifferenceNoise(residuals, 1));
  EXPECT_TRUE(EstimateDifferenceNoise(residuals, 1, 9));
  EXPECT_THROW(EstimateDifferenceNoise(residuals, 0), Error);
  residuals[5].covariance.setZero();
  EXPECT_THROW(EstimateDifferenceNoise(residuals, 1, 1), Error);
}

}  // namespace
}  // namespace uw
