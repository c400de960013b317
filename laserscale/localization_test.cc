#include "laserscale/localization.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "sim/generate.h"

namespace uw {
namespace {

Camera TestCamera() { return sim::SimConfig::DefaultCamera(); }

Rigid3d TestPose() {
  Rigid3d cam_from_world;
  cam_from_world.rotation = Eigen::Quaterniond(
      Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -1.0, 0.4).normalized()));
  cam_from_world.translation = Eigen::Vector3d(0.7, -1.2, 4.0);
  return cam_from_world;
}

// Points on a rough surface 2.5-3.5 m in front of the camera, seen inside
// the image, with Gaussian pixel noise; the first `num_outliers` get a
// random pixel instead.
std::vector<Correspondence2D3D> MakeMatches(const Camera& camera,
                                            const Rigid3d& cam_from_world,
                                            int num_points, double sigma_px,
                                            int num_outliers, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, sigma_px);
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  std::vector<Correspondence2D3D> matches;
  while (static_cast<int>(matches.size()) < num_points) {
    const Eigen::Vector2d pixel(uniform(rng) * camera.width,
                                uniform(rng) * camera.height);
    const Eigen::Vector3d ray =
        CameraModelCamFromImg(camera.model_id, camera.params.data(), pixel);
    const double depth = 2.5 + uniform(rng);
    Correspondence2D3D match;
    match.point_in_world = world_from_cam * (depth * ray);
    match.pixel = pixel + Eigen::Vector2d(noise(rng), noise(rng));
    if (static_cast<int>(matches.size()) < num_outliers) {
      match.pixel = Eigen::Vector2d(uniform(rng) * camera.width,
                                    uniform(rng) * camera.height);
    }
    matches.push_back(match);
  }
  return matches;
}

double RotationErrorDeg(const Rigid3d& a, const Rigid3d& b) {
  return a.rotation.normalized().angularDistance(b.rotation.normalized()) *
         180.0 / M_PI;
}

double CentreError(const Rigid3d& a, const Rigid3d& b) {
  return (a.Inverse().translation - b.Inverse().translation).norm();
}

TEST(LocalizeImage, NoiseFreeMatchesGiveTheExactPose) {
  const Camera camera = TestCamera();
  const Rigid3d truth = TestPose();
  const auto matches = MakeMatches(camera, truth, 200, 0.0, 0, 1);
  const Localization localization =
      LocalizeImage(camera, matches, LocalizationOptions());
  ASSERT_TRUE(localization.success) << localization.problem;
  EXPECT_EQ(localization.inliers.size(), matches.size());
  EXPECT_LT(CentreError(localization.cam_from_world, truth), 1e-9);
  EXPECT_LT(RotationErrorDeg(localization.cam_from_world, truth), 1e-8);
  EXPECT_LT(localization.rms_error_px, 1e-8);
}

TEST(LocalizeImage, RejectsOutliersAndMeasuresTheFeatureNoise) {
  const Camera camera = TestCamera();
  const Rigid3d truth = TestPose();
  // 1500 features (the thesis's count), 40 % of them outliers.
  const int num_outliers = 600;
  const auto matches = MakeMatches(camera, truth, 1500, 0.5, num_outliers, 2);
  const Localization localization =
      LocalizeImage(camera, matches, LocalizationOptions());
  ASSERT_TRUE(localization.success) << localization.problem;
  // Every true match is within 4 px (8 sigma); a random pixel lands within
  // 4 px of its point's projection with probability ~5e-5.
  int num_true_inliers = 0;
  for (const int i : localization.inliers) {
    if (i >= num_outliers) ++num_true_inliers;
  }
  EXPECT_EQ(num_true_inliers, 1500 - num_outliers);
  EXPECT_LE(localization.inliers.size(), 1500 - num_outliers + 3);
  // 900 points at 0.5 px over a 3 m deep scene: the centre to a few mm.
  EXPECT_LT(CentreError(localization.cam_from_world, truth), 0.005);
  EXPECT_LT(RotationErrorDeg(localization.cam_from_world, truth), 0.02);
  EXPECT_NEAR(localization.rms_error_px, 0.5, 0.05);
}

TEST(LocalizeImage, IsDeterministic) {
  const Camera camera = TestCamera();
  const auto matches = MakeMatches(camera, TestPose(), 500, 1.0, 200, 3);
  const Localization a = LocalizeImage(camera, matches, LocalizationOptions());
  const Localization b = LocalizeImage(camera, matches, LocalizationOptions());
  ASSERT_TRUE(a.success && b.success);
  EXPECT_EQ(a.inliers, b.inliers);
  EXPECT_EQ(a.cam_from_world.translation, b.cam_from_world.translation);
  EXPECT_EQ(a.cam_from_world.rotation.coeffs(),
            b.cam_from_world.rotation.coeffs());
}

TEST(LocalizeImage, FailsWithAReasonOnTooFewOrUnrelatedMatches) {
  const Camera camera = TestCamera();
  const auto few = MakeMatches(camera, TestPose(), 10, 0.0, 0, 4);
  Localization localization = LocalizeImage(camera, few, LocalizationOptions());
  EXPECT_FALSE(localization.success);
  EXPECT_NE(localization.problem.find("fewer than the 15 needed"),
            std::string::npos)
      << localization.problem;
  // All outliers: no pose explains 15 of them.
  const auto random = MakeMatches(camera, TestPose(), 300, 0.0, 300, 5);
  localization = LocalizeImage(camera, random, LocalizationOptions());
  EXPECT_FALSE(localization.success);
  EXPECT_FALSE(localization.problem.empty());
}

TEST(RefinePose, ConvergesFromAPerturbedPoseToTheNoiseFreeOne) {
  const Camera camera = TestCamera();
  const Rigid3d truth = TestPose();
  const auto matches = MakeMatches(camera, truth, 100, 0.0, 0, 6);
  Rigid3d pose = truth;
  pose.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY())) *
      pose.rotation;
  pose.translation += Eigen::Vector3d(0.05, -0.03, 0.1);
  ASSERT_TRUE(RefinePose(camera, matches, {}, 50, &pose));
  EXPECT_LT(CentreError(pose, truth), 1e-10);
  EXPECT_LT(RotationErrorDeg(pose, truth), 1e-9);
  EXPECT_LT(PoseRmsErrorPx(camera, matches, {}, pose), 1e-9);
}

TEST(RefinePose, RefusesPointsBehindTheCamera) {
  const Camera camera = TestCamera();
  const Rigid3d truth = TestPose();
  auto matches = MakeMatches(camera, truth, 20, 0.0, 0, 7);
  const Rigid3d world_from_cam = truth.Inverse();
  matches[3].point_in_world = world_from_cam * Eigen::Vector3d(0, 0, -1);
  Rigid3d pose = truth;
  EXPECT_FALSE(RefinePose(camera, matches, {}, 50, &pose));
  EXPECT_EQ(pose.translation, truth.translation);
}

}  // namespace
}  // namespace uw
