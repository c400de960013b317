#include "colmap_plugins/align/sim3.h"

#include "common/util/json_fields.h"

namespace uw {

Eigen::Vector3d Sim3d::operator*(const Eigen::Vector3d& point_in_a) const {
  return scale * (rotation * point_in_a) + translation;
}

Sim3d Sim3d::Inverse() const {
  Sim3d a_from_b;
  a_from_b.scale = 1.0 / scale;
  a_from_b.rotation = rotation.inverse();
  a_from_b.translation = -a_from_b.scale * (a_from_b.rotation * translation);
  return a_from_b;
}

Eigen::Matrix<double, 3, 4> Sim3d::Matrix() const {
  Eigen::Matrix<double, 3, 4> matrix;
  matrix.leftCols<3>() = scale * rotation.toRotationMatrix();
  matrix.col(3) = translation;
  return matrix;
}

Sim3d operator*(const Sim3d& c_from_b, const Sim3d& b_from_a) {
  Sim3d c_from_a;
  c_from_a.scale = c_from_b.scale * b_from_a.scale;
  c_from_a.rotation = (c_from_b.rotation * b_from_a.rotation).normalized();
  c_from_a.translation = c_from_b * b_from_a.translation;
  return c_from_a;
}

namespace {

// cam_from_b for a pose cam_from_a: the camera frame is scaled with the
// world, x_cam' = scale * x_cam, so that cam_from_b stays rigid:
// R' = R_cam R^T, t' = scale * t_cam - R' t.
Rigid3d TransformPose(const Sim3d& b_from_a, const Rigid3d& cam_from_a) {
  Rigid3d cam_from_b;
  cam_from_b.rotation = (cam_from_a.rotation.normalized() *
                         b_from_a.rotation.normalized().inverse())
                            .normalized();
  cam_from_b.translation = b_from_a.scale * cam_from_a.translation -
                           (cam_from_b.rotation * b_from_a.translation);
  return cam_from_b;
}

}  // namespace

void TransformReconstruction(const Sim3d& b_from_a,
                             Reconstruction* reconstruction) {
  for (Point3D& point3D : reconstruction->Points3D()) {
    point3D.xyz = b_from_a * point3D.xyz;
  }
  for (Image& image : reconstruction->Images()) {
    image.cam_from_world = TransformPose(b_from_a, image.cam_from_world);
  }
  for (Frame& frame : reconstruction->Frames()) {
    frame.rig_from_world = TransformPose(b_from_a, frame.rig_from_world);
  }
  // cam_from_world = sensor_from_rig * rig_from_world holds in scaled
  // camera units only if the rig's lever arms scale too.
  for (Rig& rig : reconstruction->Rigs()) {
    for (RigSensor& sensor : rig.non_ref_sensors) {
      if (sensor.sensor_from_rig) {
        sensor.sensor_from_rig->translation *= b_from_a.scale;
      }
    }
  }
}

nlohmann::json ToJson(const Sim3d& sim3) {
  nlohmann::json matrix = nlohmann::json::array();
  const Eigen::Matrix<double, 3, 4> m = sim3.Matrix();
  for (int r = 0; r < 3; ++r) {
    matrix.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  }
  return {{"scale", sim3.scale},
          {"qvec",
           {sim3.rotation.w(), sim3.rotation.x(), sim3.rotation.y(),
            sim3.rotation.z()}},
          {"tvec", ToJson(sim3.translation)},
          {"matrix", matrix}};
}

}  // namespace uw
