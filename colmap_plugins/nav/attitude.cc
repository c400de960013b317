#include "colmap_plugins/nav/attitude.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace uw {

Eigen::Matrix3d WorldFromVehicleRotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d RollPitchYawFromRotation(const Eigen::Matrix3d& rotation) {
  // R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch).
  const double pitch = std::asin(std::clamp(-rotation(2, 0), -1.0, 1.0));
  const double roll = std::atan2(rotation(2, 1), rotation(2, 2));
  const double yaw = std::atan2(rotation(1, 0), rotation(0, 0));
  return Eigen::Vector3d(roll, pitch, yaw);
}

Eigen::Matrix3d WorldRotationFromRollPitchYawJacobian(
    const Eigen::Vector3d& rpy) {
  // d/droll of Rz Ry Rx = Rz Ry [x]x Rx = [Rz Ry x]x R, and likewise.
  const Eigen::Matrix3d yaw_rotation =
      Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d pitch_rotation =
      Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Matrix3d jacobian;
  jacobian.col(0) = yaw_rotation * pitch_rotation * Eigen::Vector3d::UnitX();
  jacobian.col(1) = yaw_rotation * Eigen::Vector3d::UnitY();
  jacobian.col(2) = Eigen::Vector3d::UnitZ();
  return jacobian;
}

Eigen::Matrix3d WorldRotationCovariance(const Eigen::Vector3d& rpy,
                                        const Eigen::Vector3d& rpy_sigma) {
  const Eigen::Matrix3d jacobian = WorldRotationFromRollPitchYawJacobian(rpy);
  return jacobian * rpy_sigma.cwiseAbs2().asDiagonal() * jacobian.transpose();
}

}  // namespace uw
