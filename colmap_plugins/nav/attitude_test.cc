#include "colmap_plugins/nav/attitude.h"

#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace uw {
namespace {

// w with rotation = Exp(w).
Eigen::Vector3d Log(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

TEST(Attitude, RollPitchYawRoundTripAndConvention) {
  for (const Eigen::Vector3d& rpy :
       {Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(-3.0, 1.4, -3.1),
        Eigen::Vector3d(0.0, 0.0, M_PI)}) {
    EXPECT_LT(
        (RollPitchYawFromRotation(WorldFromVehicleRotation(rpy)) - rpy).norm(),
        1e-12)
        << rpy.transpose();
  }
  // Yaw 90 deg: the bow (vehicle x) points north (world y).
  EXPECT_LT(
      (WorldFromVehicleRotation({0, 0, M_PI / 2}) * Eigen::Vector3d::UnitX() -
       Eigen::Vector3d::UnitY())
          .norm(),
      1e-15);
  // Positive pitch puts the bow down (right-handed about y).
  EXPECT_LT(
      (WorldFromVehicleRotation({0, 0.5, 0}) * Eigen::Vector3d::UnitX()).z(),
      0.0);
}

TEST(Attitude, JacobianMatchesNumericDifferences) {
  const double h = 1e-6;
  double worst = 0.0;
  for (const Eigen::Vector3d& rpy :
       {Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(-2.0, 1.2, 2.5),
        Eigen::Vector3d(0.4, -1.5, -3.0)}) {
    const Eigen::Matrix3d jacobian = WorldRotationFromRollPitchYawJacobian(rpy);
    const Eigen::Matrix3d rotation = WorldFromVehicleRotation(rpy);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(k);
      const Eigen::Vector3d numeric =
          (Log(WorldFromVehicleRotation(rpy + step) * rotation.transpose()) -
           Log(WorldFromVehicleRotation(rpy - step) * rotation.transpose())) /
          (2 * h);
      worst = std::max(worst, (numeric - jacobian.col(k)).norm());
    }
  }
  std::cout << "[ figures ] max |analytic - numeric| of d w / d rpy: " << worst
            << "\n";
  EXPECT_LT(worst, 1e-8);
}

// The covariance of Log(R(rpy + e) R(rpy)^T) over Gaussian e.
TEST(Attitude, RotationCovarianceMatchesMonteCarlo) {
  const Eigen::Vector3d rpy(0.3, -0.6, 2.0);
  const Eigen::Vector3d sigma = Eigen::Vector3d(1.0, 0.5, 2.0) * M_PI / 180;
  const Eigen::Matrix3d expected = WorldRotationCovariance(rpy, sigma);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Matrix3d rotation = WorldFromVehicleRotation(rpy);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  const int draws = 40000;
  for (int i = 0; i < draws; ++i) {
    const Eigen::Vector3d error(sigma.x() * normal(rng),
                                sigma.y() * normal(rng),
                                sigma.z() * normal(rng));
    const Eigen::Vector3d w =
        Log(WorldFromVehicleRotation(rpy + error) * rotation.transpose());
    sum += w * w.transpose();
  }
  const Eigen::Matrix3d sampled = sum / draws;
  const double relative = (sampled - expected).norm() / expected.norm();
  std::cout << "[ figures ] Monte Carlo vs propagated rotation covariance: "
            << relative << " relative (Frobenius, 40000 draws)\n";
  EXPECT_LT(relative, 0.03);
  // Zero sigmas, zero covariance.
  EXPECT_EQ(WorldRotationCovariance(rpy, Eigen::Vector3d::Zero()),
            Eigen::Matrix3d::Zero());
}

}  // namespace
}  // namespace uw
