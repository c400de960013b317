#include "calib/mission_scene_testing.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/random.h"

namespace uw::testing_mission {
namespace {
constexpr double kDegree = M_PI / 180.0;
}  // namespace

Camera SurveyCamera() {
  Camera camera;
  camera.model_id = CameraModelId::kSimpleRadial;
  camera.width = 1024;
  camera.height = 768;
  camera.params = {850.0, 512.0, 384.0, -0.04};
  return camera;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDegree;
}

TriangleMesh Floor(double scale) {
  TriangleMesh mesh;
  const int n = 57;  // 14 m in 0.25 m steps
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = -2.0 + 0.25 * i;
      const double y = -2.0 + 0.25 * j;
      const double z = 0.3 * std::sin(0.7 * x) * std::cos(0.5 * y) +
                       0.1 * std::sin(1.9 * x + 2.3 * y);
      mesh.vertices.push_back(scale * Eigen::Vector3d(x, y, z));
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i;
      mesh.triangles.emplace_back(a, a + 1, a + n + 1);
      mesh.triangles.emplace_back(a, a + n + 1, a + n);
    }
  }
  return mesh;
}

Mission MakeMission(const RayCaster& floor, const LaserSetup& truth,
                    int num_images, double sigma_px, uint64_t seed,
                    double max_altitude_m) {
  const Camera camera = SurveyCamera();
  SplitMix64Stream random(seed);
  Mission mission;
  mission.spots.resize(truth.lasers.size());
  const Eigen::Matrix3d down =
      (Eigen::Matrix3d() << 1, 0, 0, 0, -1, 0, 0, 0, -1).finished();
  for (int i = 0; i < num_images; ++i) {
    const Eigen::Matrix3d tilt =
        (Eigen::AngleAxisd(random.Uniform(-8, 8) * kDegree,
                           Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(random.Uniform(-8, 8) * kDegree,
                           Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    const Eigen::Matrix3d world_from_cam = (tilt * down).transpose();
    const Eigen::Vector3d centre(
        random.Uniform(1, 9), random.Uniform(1, 9),
        1.5 + (max_altitude_m - 1.5) * i / (num_images - 1));
    Rigid3d cam_from_world;
    cam_from_world.rotation = Eigen::Quaterniond(world_from_cam.transpose());
    cam_from_world.translation = -(world_from_cam.transpose() * centre);
    mission.cam_from_world.push_back(cam_from_world);
    for (size_t l = 0; l < truth.lasers.size(); ++l) {
      const Laser& laser = truth.lasers[l];
      const auto hit =
          floor.Intersect(centre + world_from_cam * laser.origin_in_cam,
                          world_from_cam * laser.direction_in_cam);
      if (!hit) continue;
      MissionSpot spot;
      spot.image = "L" + std::to_string(i) + ".png";
      spot.dive = i < num_images / 2 ? 1 : 2;
      spot.camera = camera;
      spot.cam_from_world = cam_from_world;
      spot.pixel = camera.ImgFromCam(cam_from_world * hit->point_in_world) +
                   sigma_px * random.GaussianPair();
      spot.covariance_px = sigma_px * sigma_px * Eigen::Matrix2d::Identity();
      mission.spots[l].push_back(spot);
    }
  }
  return mission;
}

std::vector<LocalizedImage> Localized(const RayCaster& floor,
                                      const Mission& mission, double k) {
  const Camera camera = SurveyCamera();
  std::vector<LocalizedImage> images;
  for (size_t i = 0; i < mission.cam_from_world.size(); ++i) {
    LocalizedImage image;
    image.name = "L" + std::to_string(i) + ".png";
    image.success = true;
    image.camera = camera;
    image.cam_from_world = mission.cam_from_world[i];
    image.cam_from_world.translation *= k;
    const Rigid3d world_from_cam = image.cam_from_world.Inverse();
    for (int v = 50; v < 768; v += 150) {
      for (int u = 50; u < 1024; u += 150) {
        const Eigen::Vector3d ray =
            world_from_cam.RotationMatrix() *
            CameraModelCamFromImg(camera.model_id, camera.params.data(),
                                  Eigen::Vector2d(u, v))
                .normalized();
        const auto hit = floor.Intersect(world_from_cam.translation, ray);
        if (hit) {
          image.inliers.push_back({Eigen::Vector2d(u, v), hit->point_in_world});
        }
      }
    }
    images.push_back(image);
  }
  return images;
}

}  // namespace uw::testing_mission
