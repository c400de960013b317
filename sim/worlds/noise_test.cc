#include "sim/worlds/noise.h"

#include <cmath>

#include <gtest/gtest.h>

namespace uw::sim {
namespace {

// Mean and standard deviation of `f` over random points in a 100 m cube.
template <typename Function>
std::pair<double, double> Moments(const Function& f, uint64_t seed) {
  SplitMix64Stream points(seed);
  double sum = 0.0, sum_squares = 0.0;
  constexpr int kCount = 200000;
  for (int k = 0; k < kCount; ++k) {
    const Eigen::Vector3d p(points.Uniform(0.0, 100.0),
                            points.Uniform(0.0, 100.0),
                            points.Uniform(0.0, 100.0));
    const double value = f(p);
    sum += value;
    sum_squares += value * value;
  }
  const double mean = sum / kCount;
  return {mean, std::sqrt(sum_squares / kCount - mean * mean)};
}

TEST(GradientNoise, ZeroMeanUnitVarianceAndZeroOnTheLattice) {
  const GradientNoise noise(7);
  const auto [mean, sigma] = Moments(noise, 1);
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(sigma, 1.0, 0.05);
  for (const Eigen::Vector3d& corner :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(3, -5, 12),
        Eigen::Vector3d(-100, 7, 1)}) {
    EXPECT_EQ(noise(corner), 0.0);
  }
}

TEST(GradientNoise, SmoothAndTheSameForTheSameSeed) {
  const GradientNoise noise(7);
  const Eigen::Vector3d p(1.3, -2.7, 0.45);
  EXPECT_EQ(noise(p), GradientNoise(7)(p));
  EXPECT_NE(noise(p), GradientNoise(8)(p));
  // Within a lattice cell and across a face (x = 2): steps of 1e-6 change
  // the value by about the gradient times the step, never by a jump.
  for (const Eigen::Vector3d& q : {p, Eigen::Vector3d(2.0 - 5e-7, 0.3, 0.6)}) {
    const double step = noise(q + Eigen::Vector3d(1e-6, 0, 0)) - noise(q);
    EXPECT_LT(std::abs(step), 1e-4);
  }
}

TEST(Fbm, UnitVarianceAndAsManyOctavesAsTheWavelengthsAllow) {
  SplitMix64Stream random(3);
  const Fbm fbm(random, 8.0, 0.1);
  const auto [mean, sigma] = Moments(fbm, 2);
  EXPECT_NEAR(mean, 0.0, 0.05);
  EXPECT_NEAR(sigma, 1.0, 0.1);
  // The same draws give the same function.
  SplitMix64Stream again(3);
  const Fbm same(again, 8.0, 0.1);
  const Eigen::Vector3d p(1.5, 2.5, -0.5);
  EXPECT_EQ(fbm(p), same(p));
  // One octave when the finest wavelength exceeds the first: the noise
  // itself at 1 / wavelength, scaled and shifted.
  SplitMix64Stream one(5);
  const Fbm single(one, 2.0, 4.0);
  const auto [single_mean, single_sigma] = Moments(single, 3);
  EXPECT_NEAR(single_mean, 0.0, 0.05);
  EXPECT_NEAR(single_sigma, 1.0, 0.1);
}

TEST(SmoothStep01, ClampsAndIsSmooth) {
  EXPECT_EQ(SmoothStep01(-1.0), 0.0);
  EXPECT_EQ(SmoothStep01(0.0), 0.0);
  EXPECT_EQ(SmoothStep01(0.5), 0.5);
  EXPECT_EQ(SmoothStep01(1.0), 1.0);
  EXPECT_EQ(SmoothStep01(3.0), 1.0);
  EXPECT_NEAR(SmoothStep01(0.25), 0.15625, 1e-15);
}

}  // namespace
}  // namespace uw::sim
