#include "sim/worlds/relief.h"

#include <cmath>

#include <gtest/gtest.h>

#include "sim/world_testing.h"

namespace uw::sim {
namespace {

TEST(Relief, AmplitudesAreTheBandsStandardDeviations) {
  ReliefOptions options;
  options.undulation_amplitude_m = 0.3;
  options.roughness_amplitude_m = 0.0;
  SplitMix64Stream random(1);
  const Relief undulation(options, 0.05, random);
  options.undulation_amplitude_m = 0.0;
  options.roughness_amplitude_m = 0.04;
  const Relief roughness(options, 0.05, random);
  SplitMix64Stream points(2);
  double undulation_squares = 0.0, roughness_squares = 0.0;
  constexpr int kCount = 100000;
  for (int k = 0; k < kCount; ++k) {
    const Eigen::Vector3d p(points.Uniform(0.0, 400.0),
                            points.Uniform(0.0, 400.0), 0.0);
    undulation_squares += std::pow(undulation(p), 2);
    roughness_squares += std::pow(roughness(p), 2);
  }
  EXPECT_NEAR(std::sqrt(undulation_squares / kCount), 0.3, 0.05);
  EXPECT_NEAR(std::sqrt(roughness_squares / kCount), 0.04, 0.005);
}

TEST(Relief, OptionsAreChecked) {
  EXPECT_NO_THROW(ReliefOptions().Check("x.relief"));
  ReliefOptions options;
  options.undulation_wavelength_m = 0.0;
  EXPECT_EQ(ErrorOf([&] { options.Check("x.relief"); }),
            "world options: x.relief.undulation_wavelength_m = 0: must be a "
            "positive number");
  options = ReliefOptions();
  options.roughness_amplitude_m = -0.1;
  EXPECT_EQ(ErrorOf([&] { options.Check("x.relief"); }),
            "world options: x.relief.roughness_amplitude_m = -0.1: must be a "
            "non-negative number");
}

}  // namespace
}  // namespace uw::sim
