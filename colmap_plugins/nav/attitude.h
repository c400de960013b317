// The attitude convention of nav.csv (docs/formats.md): roll, pitch, yaw
// with world_from_vehicle = Rz(yaw) * Ry(pitch) * Rx(roll), world East-
// North-Up, vehicle x forward, y left, z up, yaw counter-clockwise from east.
// Radians here; degrees only in files and on the command line.
#pragma once

#include <Eigen/Core>

namespace uw {

// Rotation world_from_vehicle for roll, pitch, yaw (radians).
Eigen::Matrix3d WorldFromVehicleRotation(const Eigen::Vector3d& rpy);
// Inverse of WorldFromVehicleRotation (yaw in (-pi, pi]).
Eigen::Vector3d RollPitchYawFromRotation(const Eigen::Matrix3d& rotation);

// d w / d (roll, pitch, yaw) at `rpy`, where w is the small world-frame
// rotation with WorldFromVehicleRotation(rpy + d) = Exp(w) *
// WorldFromVehicleRotation(rpy) to first order. Columns: the roll axis
// (vehicle x after pitch and yaw), the pitch axis (y after yaw) and z.
Eigen::Matrix3d WorldRotationFromRollPitchYawJacobian(
    const Eigen::Vector3d& rpy);

// Covariance (rad²) of that world-frame rotation error for independent
// roll, pitch and yaw errors of standard deviations `rpy_sigma` (rad).
// Anything mounted rigidly on the vehicle shares it.
Eigen::Matrix3d WorldRotationCovariance(const Eigen::Vector3d& rpy,
                                        const Eigen::Vector3d& rpy_sigma);

}  // namespace uw
