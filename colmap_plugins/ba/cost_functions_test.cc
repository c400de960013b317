// The BA's cost functors: zero at consistent inputs, the meaning of their
// values, and autodiff Jacobians against numeric differences.
#include <algorithm>
#include <memory>
#include <random>
#include <vector>

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <gtest/gtest.h>

#include "colmap_plugins/ba/nav_prior.h"
#include "colmap_plugins/ba/reprojection_error.h"
#include "colmap_plugins/ba/rig_prior.h"
#include "colmap_plugins/cameras/camera_models.h"
#include "colmap_plugins/scene/model.h"

namespace uw {
namespace {

struct Pose {
  double rotation[4];
  double translation[3];
};

Pose ToPose(const Rigid3d& cam_from_world) {
  const Eigen::Quaterniond q = cam_from_world.rotation.normalized();
  return {{q.w(), q.x(), q.y(), q.z()},
          {cam_from_world.translation.x(), cam_from_world.translation.y(),
           cam_from_world.translation.z()}};
}

Rigid3d RandomPose(std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Rigid3d pose;
  pose.rotation =
      Eigen::Quaterniond(Eigen::Vector4d(normal(*rng), normal(*rng),
                                         normal(*rng), normal(*rng)))
          .normalized();
  pose.translation = Eigen::Vector3d(normal(*rng), normal(*rng), normal(*rng));
  return pose;
}

Rigid3d Compose(const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
  Rigid3d c_from_a;
  c_from_a.rotation = c_from_b.rotation * b_from_a.rotation;
  c_from_a.translation =
      c_from_b.rotation * b_from_a.translation + c_from_b.translation;
  return c_from_a;
}

// Checks the cost function's Jacobians against numeric differences, with
// quaternion blocks on the quaternion manifold.
void ExpectGradientsMatch(const ceres::CostFunction& cost,
                          const std::vector<double*>& blocks,
                          const std::vector<bool>& is_quaternion) {
  ceres::QuaternionManifold quaternion;
  std::vector<const ceres::Manifold*> manifolds;
  for (const bool q : is_quaternion) {
    manifolds.push_back(q ? &quaternion : nullptr);
  }
  ceres::NumericDiffOptions numeric;
  ceres::GradientChecker checker(&cost, &manifolds, numeric);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(blocks.data(), 1e-6, &results);
  // Compared per block relative to the block's largest entry: central
  // differences leave ~1e-5 of it in every entry, which a per-entry
  // relative test would blow up on small entries.
  ASSERT_EQ(results.local_jacobians.size(), blocks.size());
  for (size_t b = 0; b < blocks.size(); ++b) {
    const Eigen::MatrixXd& autodiff = results.local_jacobians[b];
    const Eigen::MatrixXd& numeric = results.local_numeric_jacobians[b];
    const double scale = std::max(1e-9, autodiff.cwiseAbs().maxCoeff());
    EXPECT_LT((autodiff - numeric).cwiseAbs().maxCoeff(), 2e-5 * scale)
        << "block " << b << "\nautodiff\n"
        << autodiff << "\nnumeric\n"
        << numeric;
  }
}

TEST(ReprojectionErrorCostFunctor, ZeroAtTheProjectionAndGradientsMatch) {
  std::mt19937 rng(1);
  Camera camera;
  camera.model_id = CameraModelId::kOpenCV;
  camera.params = {800, 810, 500, 380, -0.05, 0.01, 0.001, -0.002};
  Pose pose = ToPose(RandomPose(&rng));
  Rigid3d cam_from_world;
  cam_from_world.rotation = Eigen::Quaterniond(
      pose.rotation[0], pose.rotation[1], pose.rotation[2], pose.rotation[3]);
  cam_from_world.translation = Eigen::Map<Eigen::Vector3d>(pose.translation);
  Eigen::Vector3d point_in_world =
      cam_from_world.Inverse() * Eigen::Vector3d(0.3, -0.2, 3.0);
  const Eigen::Vector2d observed =
      camera.ImgFromCam(cam_from_world * point_in_world);
  std::unique_ptr<ceres::CostFunction> cost(
      ReprojectionErrorCostFunctor<OpenCVCameraModel>::Create(observed, 0.5));
  const double* blocks[] = {pose.rotation, pose.translation,
                            point_in_world.data(), camera.params.data()};
  Eigen::Vector2d residual;
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_LT(residual.norm(), 1e-9);

  const std::unique_ptr<ceres::CostFunction> shifted(
      ReprojectionErrorCostFunctor<OpenCVCameraModel>::Create(
          observed + Eigen::Vector2d(2.0, -4.0), 0.5));
  ASSERT_TRUE(shifted->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_NEAR(residual.x(), -1.0, 1e-9);
  EXPECT_NEAR(residual.y(), 2.0, 1e-9);
  ExpectGradientsMatch(*shifted,
                       {pose.rotation, pose.translation, point_in_world.data(),
                        camera.params.data()},
                       {true, false, false, false});
}

TEST(PositionPriorCostFunctor, MeasuresTheCentreAgainstPriorPlusOffset) {
  std::mt19937 rng(2);
  const Rigid3d cam_from_world = RandomPose(&rng);
  Pose pose = ToPose(cam_from_world);
  const Eigen::Vector3d center = cam_from_world.Inverse().translation;
  Eigen::Vector3d offset(0.5, -1.0, 0.25);
  const Eigen::Vector3d prior = center - offset + Eigen::Vector3d(0.1, 0, 0);
  Eigen::Matrix3d sqrt_information = Eigen::Matrix3d::Identity();
  sqrt_information(0, 0) = 10.0;
  std::unique_ptr<ceres::CostFunction> cost(
      PositionPriorCostFunctor::Create(prior, sqrt_information));
  const double* blocks[] = {pose.rotation, pose.translation, offset.data()};
  Eigen::Vector3d residual;
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_NEAR(residual.x(), -1.0, 1e-12);
  EXPECT_NEAR(residual.y(), 0.0, 1e-12);
  EXPECT_NEAR(residual.z(), 0.0, 1e-12);
  ExpectGradientsMatch(*cost, {pose.rotation, pose.translation, offset.data()},
                       {true, false, false});
}

TEST(AttitudePriorCostFunctor, IsTheWorldFrameRotationVector) {
  std::mt19937 rng(3);
  const Rigid3d prior = RandomPose(&rng);
  const Eigen::Vector3d rotation_vector(0.01, -0.02, 0.03);
  // world_from_cam = Exp(w) * world_from_cam_prior.
  const Eigen::Quaterniond world_from_cam =
      Eigen::Quaterniond(Eigen::AngleAxisd(rotation_vector.norm(),
                                           rotation_vector.normalized())) *
      prior.rotation.conjugate();
  Rigid3d estimate;
  estimate.rotation = world_from_cam.conjugate();
  Pose pose = ToPose(estimate);
  std::unique_ptr<ceres::CostFunction> cost(AttitudePriorCostFunctor::Create(
      prior.rotation, 2.0 * Eigen::Matrix3d::Identity()));
  const double* blocks[] = {pose.rotation};
  Eigen::Vector3d residual;
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_LT((residual - 2.0 * rotation_vector).norm(), 1e-12);
  ExpectGradientsMatch(*cost, {pose.rotation}, {true});
}

TEST(DiveOffsetPriorCostFunctor, WhitensTheOffset) {
  Eigen::Vector3d offset(1.0, 2.0, 3.0);
  std::unique_ptr<ceres::CostFunction> cost(
      DiveOffsetPriorCostFunctor::Create(0.1 * Eigen::Matrix3d::Identity()));
  const double* blocks[] = {offset.data()};
  Eigen::Vector3d residual;
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_LT((residual - 0.1 * offset).norm(), 1e-15);
}

TEST(SqrtInformation, WhitensAndRejectsBadCovariances) {
  Eigen::Matrix3d covariance;
  covariance << 4, 1, 0, 1, 2, 0.5, 0, 0.5, 1;
  const Eigen::Matrix3d s = SqrtInformation(covariance);
  EXPECT_LT((s.transpose() * s - covariance.inverse()).norm(), 1e-12);
  EXPECT_LT(
      (s * covariance * s.transpose() - Eigen::Matrix3d::Identity()).norm(),
      1e-12);
  EXPECT_THROW(SqrtInformation(Eigen::Matrix3d::Zero()), Error);
  Eigen::Matrix3d asymmetric = covariance;
  asymmetric(0, 1) = 3.0;
  EXPECT_THROW(SqrtInformation(asymmetric), Error);
  EXPECT_THROW(SqrtInformation(Eigen::Matrix3d::Constant(NAN)), Error);
}

TEST(RigPriorCostFunctor, ZeroForARigidRigAndMeasuresDeviations) {
  std::mt19937 rng(4);
  const Rigid3d ref_from_world = RandomPose(&rng);
  Rigid3d cam_from_rig = RandomPose(&rng);
  cam_from_rig.translation *= 0.3;
  Pose ref = ToPose(ref_from_world);
  Pose cam = ToPose(Compose(cam_from_rig, ref_from_world));
  RigCameraPrior prior;
  prior.cam_from_rig = cam_from_rig.rotation;
  prior.cam_center_in_rig = cam_from_rig.Inverse().translation;
  prior.rotation_weight = 1.0;
  prior.translation_weight = 1.0;
  std::unique_ptr<ceres::CostFunction> cost(RigPriorCostFunctor::Create(prior));
  const double* blocks[] = {ref.rotation, ref.translation, cam.rotation,
                            cam.translation};
  Eigen::Matrix<double, 6, 1> residual;
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_LT(residual.norm(), 1e-12);

  // Moving camera k's centre by d (world) shows as d in the translation part.
  Rigid3d moved = Compose(cam_from_rig, ref_from_world);
  const Eigen::Vector3d d(0.01, -0.02, 0.005);
  moved.translation -= moved.rotation * d;
  cam = ToPose(moved);
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_LT(residual.head<3>().norm(), 1e-12);
  EXPECT_LT((residual.tail<3>() - d).norm(), 1e-12);
  ExpectGradientsMatch(
      *cost, {ref.rotation, ref.translation, cam.rotation, cam.translation},
      {true, false, true, false});
}

TEST(InterpolatedRigPriorCostFunctor, FollowsLinearMotionWithSlerp) {
  std::mt19937 rng(5);
  const Rigid3d a_from_world = RandomPose(&rng);
  // b: rotated by 10 degrees about some axis and moved 0.4 m.
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, 1.0, -0.3).normalized();
  const double angle = 10.0 * M_PI / 180.0;
  Rigid3d b_from_world;
  b_from_world.rotation = a_from_world.rotation *
                          Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
  const Eigen::Vector3d a_center = a_from_world.Inverse().translation;
  const Eigen::Vector3d b_center = a_center + Eigen::Vector3d(0.4, 0.1, -0.05);
  b_from_world.translation = -(b_from_world.rotation * b_center);
  const double alpha = 0.3;
  Rigid3d rig_from_world;
  rig_from_world.rotation =
      a_from_world.rotation *
      Eigen::Quaterniond(Eigen::AngleAxisd(alpha * angle, axis));
  rig_from_world.translation =
      -(rig_from_world.rotation * (a_center + alpha * (b_center - a_center)));
  Rigid3d cam_from_rig = RandomPose(&rng);
  cam_from_rig.translation *= 0.3;
  Pose a = ToPose(a_from_world);
  Pose b = ToPose(b_from_world);
  Pose cam = ToPose(Compose(cam_from_rig, rig_from_world));
  RigCameraPrior prior;
  prior.cam_from_rig = cam_from_rig.rotation;
  prior.cam_center_in_rig = cam_from_rig.Inverse().translation;
  std::unique_ptr<ceres::CostFunction> cost(
      InterpolatedRigPriorCostFunctor::Create(prior, alpha));
  const double* blocks[] = {a.rotation,    a.translation, b.rotation,
                            b.translation, cam.rotation,  cam.translation};
  Eigen::Matrix<double, 6, 1> residual;
  ASSERT_TRUE(cost->Evaluate(blocks, residual.data(), nullptr));
  EXPECT_LT(residual.norm(), 1e-12);
  // Pairing with a alone would see the motion as a rig error.
  std::unique_ptr<ceres::CostFunction> naive(
      RigPriorCostFunctor::Create(prior));
  const double* naive_blocks[] = {a.rotation, a.translation, cam.rotation,
                                  cam.translation};
  ASSERT_TRUE(naive->Evaluate(naive_blocks, residual.data(), nullptr));
  EXPECT_GT(residual.tail<3>().norm(), 0.1);
  ExpectGradientsMatch(*cost,
                       {a.rotation, a.translation, b.rotation, b.translation,
                        cam.rotation, cam.translation},
                       {true, false, true, false, true, false});
}

}  // namespace
}  // namespace uw
