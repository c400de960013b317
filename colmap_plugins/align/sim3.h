// Similarity transforms between two world frames, and applying one to a
// COLMAP model (geo-registration, alignment to navigation or to the truth).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "colmap_plugins/scene/model.h"

namespace uw {

// b_from_a: x_b = scale * rotation * x_a + translation.
struct Sim3d {
  double scale = 1.0;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& point_in_a) const;
  Sim3d Inverse() const;
  // The 3x4 matrix [scale * R | t].
  Eigen::Matrix<double, 3, 4> Matrix() const;
};

// c_from_a = c_from_b * b_from_a.
Sim3d operator*(const Sim3d& c_from_b, const Sim3d& b_from_a);

// Moves a model from frame a to frame b. Points and camera centres map by
// b_from_a; cameras keep their orientation relative to the scene, and the
// translations of cam_from_world, rig_from_world and sensor_from_rig are
// scaled so that every image still sees its points where it did (COLMAP's
// Reconstruction::Transform). Quaternions are written normalised.
void TransformReconstruction(const Sim3d& b_from_a,
                             Reconstruction* reconstruction);

// {"scale": s, "qvec": [w, x, y, z], "tvec": [x, y, z],
//  "matrix": 3 rows of [s R | t]}.
nlohmann::json ToJson(const Sim3d& sim3);

}  // namespace uw
