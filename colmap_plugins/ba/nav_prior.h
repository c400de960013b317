// Navigation priors on camera poses, for Ceres: the camera centre against
// the navigation position (with the dive's offset) and, optionally, the
// camera attitude against the navigation attitude.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace uw {

// World position of the centre of camera cam_from_world: -R^T t.
template <typename T>
void CameraCenterInWorld(const T* cam_from_world_rotation,
                         const T* cam_from_world_translation,
                         T* center_in_world) {
  const T world_from_cam_rotation[4] = {
      cam_from_world_rotation[0], -cam_from_world_rotation[1],
      -cam_from_world_rotation[2], -cam_from_world_rotation[3]};
  ceres::UnitQuaternionRotatePoint(world_from_cam_rotation,
                                   cam_from_world_translation, center_in_world);
  for (int i = 0; i < 3; ++i) center_in_world[i] = -center_in_world[i];
}

// Residual (3): sqrt_information * (camera centre in world - (navigation
// position + dive offset)). The dive offset is the per-dive bias of the
// navigation (thesis ch. 4 §5.2.2: E_i(n) = t_i - (C_i + delta_d)); the
// reference dive's offset block is held constant at zero. sqrt_information
// is the upper-triangular factor of the prior's information matrix times the
// objective's weight, so that the squared residual is a weighted
// Mahalanobis distance.
// Parameter blocks: cam_from_world rotation (w, x, y, z), translation (3),
// dive offset in world (3).
class PositionPriorCostFunctor {
 public:
  PositionPriorCostFunctor(const Eigen::Vector3d& position_in_world,
                           const Eigen::Matrix3d& sqrt_information)
      : position_in_world_(position_in_world),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation,
                  const T* dive_offset_in_world, T* residuals) const {
    T center[3];
    CameraCenterInWorld(cam_from_world_rotation, cam_from_world_translation,
                        center);
    Eigen::Matrix<T, 3, 1> error;
    for (int i = 0; i < 3; ++i) {
      error(i) =
          center[i] - (T(position_in_world_(i)) + dive_offset_in_world[i]);
    }
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residuals);
    whitened = sqrt_information_.cast<T>() * error;
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& position_in_world,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<PositionPriorCostFunctor, 3, 4, 3,
                                           3>(
        new PositionPriorCostFunctor(position_in_world, sqrt_information));
  }

 private:
  Eigen::Vector3d position_in_world_;
  Eigen::Matrix3d sqrt_information_;
};

// Residual (3, rad, whitened): sqrt_information * w, where w is the
// world-frame rotation vector taking the prior camera attitude to the
// estimated one: world_from_cam = Exp(w) * world_from_cam_prior. Navigation
// attitude errors (roll, pitch, heading) live in the world frame, which is
// why the error is expressed there rather than in the camera frame.
// Parameter block: cam_from_world rotation (w, x, y, z).
class AttitudePriorCostFunctor {
 public:
  AttitudePriorCostFunctor(const Eigen::Quaterniond& cam_from_world_prior,
                           const Eigen::Matrix3d& sqrt_information)
      : cam_from_world_prior_(cam_from_world_prior.normalized()),
        sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* cam_from_world_rotation, T* residuals) const {
    // Exp(w) = world_from_cam_est * cam_from_world_prior, i.e. the
    // quaternion conj(q_est) * q_prior.
    const T world_from_cam[4] = {
        cam_from_world_rotation[0], -cam_from_world_rotation[1],
        -cam_from_world_rotation[2], -cam_from_world_rotation[3]};
    const T prior[4] = {
        T(cam_from_world_prior_.w()), T(cam_from_world_prior_.x()),
        T(cam_from_world_prior_.y()), T(cam_from_world_prior_.z())};
    T delta[4];
    ceres::QuaternionProduct(world_from_cam, prior, delta);
    Eigen::Matrix<T, 3, 1> rotation_vector;
    ceres::QuaternionToAngleAxis(delta, rotation_vector.data());
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residuals);
    whitened = sqrt_information_.cast<T>() * rotation_vector;
    return true;
  }

  static ceres::CostFunction* Create(
      const Eigen::Quaterniond& cam_from_world_prior,
      const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<AttitudePriorCostFunctor, 3, 4>(
        new AttitudePriorCostFunctor(cam_from_world_prior, sqrt_information));
  }

 private:
  Eigen::Quaterniond cam_from_world_prior_;
  Eigen::Matrix3d sqrt_information_;
};

// Residual (3): sqrt_information * dive offset. A weak prior that keeps an
// offset finite when its dive barely overlaps the others.
class DiveOffsetPriorCostFunctor {
 public:
  explicit DiveOffsetPriorCostFunctor(const Eigen::Matrix3d& sqrt_information)
      : sqrt_information_(sqrt_information) {}

  template <typename T>
  bool operator()(const T* dive_offset_in_world, T* residuals) const {
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residuals);
    whitened = sqrt_information_.cast<T>() *
               Eigen::Map<const Eigen::Matrix<T, 3, 1>>(dive_offset_in_world);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<DiveOffsetPriorCostFunctor, 3, 3>(
        new DiveOffsetPriorCostFunctor(sqrt_information));
  }

 private:
  Eigen::Matrix3d sqrt_information_;
};

// Upper-triangular S with S^T S = inverse(covariance) (a whitening matrix).
// Throws uw::Error if the covariance is not symmetric positive definite.
Eigen::Matrix3d SqrtInformation(const Eigen::Matrix3d& covariance);

}  // namespace uw
