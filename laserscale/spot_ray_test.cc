#include "laserscale/spot_ray.h"

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "common/mesh/test_meshes.h"
#include "laserscale/scale_estimators.h"
#include "sim/laser.h"

namespace uw {
namespace {

// A camera 3 m in front of a wall tilted 25 degrees about its vertical axis
// (a view that is neither square-on nor flat), with radial distortion.
struct Scene {
  TriangleMesh mesh;
  Camera camera;
  Rigid3d cam_from_world;
};

Scene MakeScene(double model_scale) {
  Scene scene;
  // The wall: the plane through (0, 0, 3) with normal tilted about y.
  const double tilt = 25.0 * M_PI / 180.0;
  const Eigen::Vector3d u(std::cos(tilt), 0.0, std::sin(tilt));
  const Eigen::Vector3d v(0.0, 1.0, 0.0);
  AddGrid(model_scale * (Eigen::Vector3d(0, 0, 3) - 4.0 * u - 4.0 * v),
          model_scale * 8.0 * u, model_scale * 8.0 * v, 8, 8, &scene.mesh);
  scene.camera.camera_id = 1;
  scene.camera.model_id = CameraModelId::kSimpleRadial;
  scene.camera.width = 1024;
  scene.camera.height = 768;
  scene.camera.params = {850.0, 512.0, 384.0, -0.04};
  // The world frame is the camera's, turned and moved (scaled with the
  // model, as an SfM model's camera centres are).
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Vector3d offset(5.0, -2.0, 1.0);
  for (Eigen::Vector3d& vertex : scene.mesh.vertices) {
    vertex = rotation * vertex + model_scale * offset;
  }
  scene.cam_from_world.rotation = rotation.conjugate();
  scene.cam_from_world.translation =
      -(rotation.conjugate() * offset) * model_scale;
  return scene;
}

// Where a beam meets the wall, in the camera frame (metres): the beam's
// line intersected with the wall's plane.
Eigen::Vector3d TrueHitInCam(const Laser& laser) {
  const double tilt = 25.0 * M_PI / 180.0;
  const Eigen::Vector3d normal(-std::sin(tilt), 0.0, std::cos(tilt));
  const double t =
      (Eigen::Vector3d(0, 0, 3) - laser.origin_in_cam).dot(normal) /
      laser.direction_in_cam.dot(normal);
  return laser.origin_in_cam + t * laser.direction_in_cam;
}

// The chain a laser image goes through: project the true hit to a pixel
// (with distortion), cast that pixel back onto the model's mesh, and run
// FUM on it. With a model k times too large it gives 1/k, for each of the
// thesis's set-ups.
TEST(CastSpot, FindsTheHitAndFumTheModelScale) {
  for (const double k : {0.237, 1.0, 4.2}) {
    const Scene scene = MakeScene(k);
    const RayCaster caster(scene.mesh);
    for (const char* setup_name : {"A", "B", "C"}) {
      sim::LaserOptions options;
      options.setup = setup_name;
      for (const Laser& laser : sim::TrueLaserSetup(options).lasers) {
        const Eigen::Vector3d hit_in_cam = TrueHitInCam(laser);
        const Eigen::Vector2d spot = scene.camera.ImgFromCam(hit_in_cam);
        const SpotHit hit =
            CastSpot(caster, scene.camera, scene.cam_from_world, spot);
        ASSERT_TRUE(hit.point_in_world.has_value()) << hit.problem;
        const Eigen::Vector3d model_hit_in_cam =
            scene.cam_from_world * *hit.point_in_world;
        EXPECT_LT((model_hit_in_cam - k * hit_in_cam).norm(), 1e-9 * k);
        const ScaleEstimate scale = FumScale(laser, model_hit_in_cam);
        ASSERT_TRUE(scale.scale.has_value()) << scale.problem;
        EXPECT_NEAR(*scale.scale * k, 1.0, 1e-9)
            << setup_name << " " << laser.name << " k " << k;
      }
    }
  }
}

TEST(CastSpot, ReportsSpotsItCannotPlace) {
  const Scene scene = MakeScene(1.0);
  const RayCaster caster(scene.mesh);
  const auto problem = [&](const Eigen::Vector2d& spot) {
    const SpotHit hit =
        CastSpot(caster, scene.camera, scene.cam_from_world, spot);
    EXPECT_FALSE(hit.point_in_world.has_value());
    return hit.problem;
  };
  EXPECT_NE(problem({-3.0, 100.0}).find("outside the 1024x768 image"),
            std::string::npos);
  EXPECT_NE(problem({NAN, 100.0}).find("not finite"), std::string::npos);
  // A wall only 0.8 m wide: the image's left edge sees past it.
  Scene narrow = scene;
  for (Eigen::Vector3d& vertex : narrow.mesh.vertices) {
    const Eigen::Vector3d in_cam = scene.cam_from_world * vertex;
    vertex = scene.cam_from_world.Inverse() *
             Eigen::Vector3d(0.1 * in_cam.x(), in_cam.y(), in_cam.z());
  }
  const RayCaster narrow_caster(narrow.mesh);
  const SpotHit miss = CastSpot(narrow_caster, narrow.camera,
                                narrow.cam_from_world, {5.0, 384.0});
  EXPECT_FALSE(miss.point_in_world.has_value());
  EXPECT_NE(miss.problem.find("meets no surface"), std::string::npos);
}

}  // namespace
}  // namespace uw
