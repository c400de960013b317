// Soft rig constraints, for Ceres: the pose of a rig camera against the pose
// the rig calibration predicts from the reference camera (thesis ch. 6,
// "soft enforcement of known relative constraints"; spec ch5_6 §2.2).
//
// Unsynchronised cameras fire dt after the reference camera, when the
// vehicle has moved on: the rig pose at the camera's own time is then
// interpolated between the two reference images around it (centres
// linearly, attitudes by slerp), the same motion model under which
// navigation is interpolated at image times. Without interpolation (alpha
// fixed at 0, one reference image), the vehicle's motion during dt appears
// as a rig error, which the constraint's sigma then has to absorb.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_plugins/ba/nav_prior.h"

namespace uw {

namespace rig_internal {

// Residual of camera k (q_k, t_k) against the rig pose rig_from_world
// (q_rig, centre of the rig in world) composed with cam_from_rig:
// rotation vector of world_from_cam_predicted * cam_from_world (world
// frame, rad) and centre difference (world frame, m), each whitened.
template <typename T>
void RigResidual(const T* rig_from_world_rotation, const T* rig_center,
                 const T* cam_rotation, const T* cam_translation,
                 const Eigen::Quaterniond& cam_from_rig,
                 const Eigen::Vector3d& cam_center_in_rig,
                 double rotation_weight, double translation_weight,
                 T* residuals) {
  const T cam_from_rig_rotation[4] = {T(cam_from_rig.w()), T(cam_from_rig.x()),
                                      T(cam_from_rig.y()), T(cam_from_rig.z())};
  T predicted[4];
  ceres::QuaternionProduct(cam_from_rig_rotation, rig_from_world_rotation,
                           predicted);
  const T world_from_predicted[4] = {predicted[0], -predicted[1], -predicted[2],
                                     -predicted[3]};
  T delta[4];
  ceres::QuaternionProduct(world_from_predicted, cam_rotation, delta);
  ceres::QuaternionToAngleAxis(delta, residuals);

  const T world_from_rig[4] = {
      rig_from_world_rotation[0], -rig_from_world_rotation[1],
      -rig_from_world_rotation[2], -rig_from_world_rotation[3]};
  const T offset_in_rig[3] = {T(cam_center_in_rig.x()),
                              T(cam_center_in_rig.y()),
                              T(cam_center_in_rig.z())};
  T offset_in_world[3];
  ceres::UnitQuaternionRotatePoint(world_from_rig, offset_in_rig,
                                   offset_in_world);
  T cam_center[3];
  CameraCenterInWorld(cam_rotation, cam_translation, cam_center);
  for (int i = 0; i < 3; ++i) {
    residuals[i] *= T(rotation_weight);
    residuals[3 + i] = T(translation_weight) *
                       (cam_center[i] - (rig_center[i] + offset_in_world[i]));
  }
}

}  // namespace rig_internal

// Relative-pose weights of a rig camera: the residual's rotation part is
// divided by rotation_sigma (rad), its translation part by
// translation_sigma (m), both then multiplied by `weight` (the objective's).
struct RigCameraPrior {
  Eigen::Quaterniond cam_from_rig = Eigen::Quaterniond::Identity();
  Eigen::Vector3d cam_center_in_rig = Eigen::Vector3d::Zero();
  double rotation_weight = 1.0;     // weight / rotation_sigma
  double translation_weight = 1.0;  // weight / translation_sigma
};

// Residual (6): rig camera k against the reference camera image taken at
// (nearly) the same time. Parameter blocks: reference cam_from_world
// rotation (4) and translation (3), camera k's rotation (4), translation (3).
class RigPriorCostFunctor {
 public:
  explicit RigPriorCostFunctor(const RigCameraPrior& prior) : prior_(prior) {}

  template <typename T>
  bool operator()(const T* ref_rotation, const T* ref_translation,
                  const T* cam_rotation, const T* cam_translation,
                  T* residuals) const {
    T ref_center[3];
    CameraCenterInWorld(ref_rotation, ref_translation, ref_center);
    rig_internal::RigResidual(ref_rotation, ref_center, cam_rotation,
                              cam_translation, prior_.cam_from_rig,
                              prior_.cam_center_in_rig, prior_.rotation_weight,
                              prior_.translation_weight, residuals);
    return true;
  }

  static ceres::CostFunction* Create(const RigCameraPrior& prior) {
    return new ceres::AutoDiffCostFunction<RigPriorCostFunctor, 6, 4, 3, 4, 3>(
        new RigPriorCostFunctor(prior));
  }

 private:
  RigCameraPrior prior_;
};

// Residual (6): rig camera k, fired at time t, against the rig pose
// interpolated at t between reference images a (time t_a) and b (t_b):
// alpha = (t - t_a) / (t_b - t_a). Parameter blocks: a's rotation and
// translation, b's rotation and translation, camera k's rotation and
// translation.
class InterpolatedRigPriorCostFunctor {
 public:
  InterpolatedRigPriorCostFunctor(const RigCameraPrior& prior, double alpha)
      : prior_(prior), alpha_(alpha) {}

  template <typename T>
  bool operator()(const T* a_rotation, const T* a_translation,
                  const T* b_rotation, const T* b_translation,
                  const T* cam_rotation, const T* cam_translation,
                  T* residuals) const {
    // Slerp of cam_from_world: q(alpha) = q_a * Exp(alpha Log(conj(q_a) q_b)).
    const T a_conjugate[4] = {a_rotation[0], -a_rotation[1], -a_rotation[2],
                              -a_rotation[3]};
    T a_to_b[4];
    ceres::QuaternionProduct(a_conjugate, b_rotation, a_to_b);
    T angle_axis[3];
    ceres::QuaternionToAngleAxis(a_to_b, angle_axis);
    for (T& value : angle_axis) value *= T(alpha_);
    T partial[4];
    ceres::AngleAxisToQuaternion(angle_axis, partial);
    T rig_rotation[4];
    ceres::QuaternionProduct(a_rotation, partial, rig_rotation);

    T a_center[3];
    T b_center[3];
    CameraCenterInWorld(a_rotation, a_translation, a_center);
    CameraCenterInWorld(b_rotation, b_translation, b_center);
    T rig_center[3];
    for (int i = 0; i < 3; ++i) {
      rig_center[i] = a_center[i] + T(alpha_) * (b_center[i] - a_center[i]);
    }
    rig_internal::RigResidual(rig_rotation, rig_center, cam_rotation,
                              cam_translation, prior_.cam_from_rig,
                              prior_.cam_center_in_rig, prior_.rotation_weight,
                              prior_.translation_weight, residuals);
    return true;
  }

  static ceres::CostFunction* Create(const RigCameraPrior& prior,
                                     double alpha) {
    return new ceres::AutoDiffCostFunction<InterpolatedRigPriorCostFunctor, 6,
                                           4, 3, 4, 3, 4, 3>(
        new InterpolatedRigPriorCostFunctor(prior, alpha));
  }

 private:
  RigCameraPrior prior_;
  double alpha_;
};

}  // namespace uw
