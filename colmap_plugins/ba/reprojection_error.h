// Reprojection residual of a COLMAP camera model, for Ceres.
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

namespace uw {

// Residual (2, px): weight * (projection of point_in_world through
// cam_from_world and the camera - observed pixel). Parameter blocks:
// cam_from_world rotation (Hamilton w, x, y, z; COLMAP's order, Ceres'
// QuaternionManifold), cam_from_world translation (3), point_in_world (3),
// camera params (CameraModel::kNumParams, COLMAP's order). `weight` carries
// the thesis's 1/sqrt(M) normalisation (Eq. 2), so that the reprojection
// objective is a mean over observations.
template <typename CameraModel>
class ReprojectionErrorCostFunctor {
 public:
  ReprojectionErrorCostFunctor(const Eigen::Vector2d& observed, double weight)
      : observed_(observed), weight_(weight) {}

  template <typename T>
  bool operator()(const T* cam_from_world_rotation,
                  const T* cam_from_world_translation, const T* point_in_world,
                  const T* camera_params, T* residuals) const {
    T point_in_cam[3];
    ceres::UnitQuaternionRotatePoint(cam_from_world_rotation, point_in_world,
                                     point_in_cam);
    for (int i = 0; i < 3; ++i) {
      point_in_cam[i] += cam_from_world_translation[i];
    }
    T x;
    T y;
    CameraModel::ImgFromCam(camera_params, point_in_cam[0], point_in_cam[1],
                            point_in_cam[2], &x, &y);
    residuals[0] = T(weight_) * (x - T(observed_.x()));
    residuals[1] = T(weight_) * (y - T(observed_.y()));
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed,
                                     double weight) {
    return new ceres::AutoDiffCostFunction<ReprojectionErrorCostFunctor, 2, 4,
                                           3, 3, CameraModel::kNumParams>(
        new ReprojectionErrorCostFunctor(observed, weight));
  }

 private:
  Eigen::Vector2d observed_;
  double weight_;
};

}  // namespace uw
