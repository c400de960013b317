// A small synthetic survey for the BA's unit tests: down-looking cameras
// over a gently undulating floor, exact observations plus Gaussian pixel
// noise, and navigation priors with Gaussian noise and per-dive biases.
// Everything is known, so tests compare against the truth directly.
#pragma once

#include <algorithm>
#include <random>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/scene/model.h"

namespace uw::test {

struct TestSceneOptions {
  int num_lines = 3;
  int images_per_line = 8;
  double spacing_m = 0.6;
  double line_spacing_m = 1.0;
  double altitude_m = 3.0;
  // Sideways and vertical sine wiggles of the track (amplitude, m), so that
  // a single line is not collinear.
  double wiggle_m = 0.0;
  int num_points = 1500;
  // Images (line, index along the line) not taken: a coverage gap.
  std::vector<std::pair<int, int>> missing_images;
  // Images taken while the vehicle hovered: at station (line, index),
  // `count` images `spacing_m` apart along the line instead of one. With
  // the stations around it missing, the floor under it is seen from a
  // short baseline only.
  struct Hover {
    int line = 0;
    int index = 0;
    int count = 1;
    double spacing_m = 0.0;
  };
  std::vector<Hover> hovers;
  double pixel_sigma = 0.5;
  double nav_sigma_m = 0.3;
  // Attitude priors (world-frame rotation noise, rad); drawn from their own
  // random stream, so the other draws do not depend on them.
  double attitude_sigma_rad = 0.002;
  // Lines with index >= first_line_of_dive_2 belong to dive 2 (none if
  // >= num_lines), whose navigation is off by dive2_bias.
  int first_line_of_dive_2 = 1000;
  Eigen::Vector3d dive2_bias = Eigen::Vector3d::Zero();
  // A second camera (id 2, the first's intrinsics) rigidly mounted beside
  // the first: every station also takes an image of it, at the same time,
  // with no navigation prior of its own (the log has the vehicle, here
  // camera 1). TestScene::rig states the mount with the sigmas below.
  bool rig = false;
  Rigid3d rig_cam2_from_cam1 = {
      Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(-0.3, 0.0, 0.0)};
  double rig_rotation_sigma_rad = 0.002;
  double rig_translation_sigma_m = 0.005;
  unsigned seed = 1;
};

struct TestScene {
  Reconstruction truth;
  Reconstruction observed;  // truth poses/points, noisy observations
  std::vector<ImagePosePrior> priors;
  // With TestSceneOptions::rig: the mount, and every image's time (its
  // station's index, s), which pairs the rig's images.
  SoftRig rig;
  std::unordered_map<image_t, double> image_times;
};

// Exp of a rotation vector (rad); the identity for a zero vector.
inline Eigen::Quaterniond RotationFromVector(const Eigen::Vector3d& w) {
  if (w.norm() == 0.0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(w.norm(), w.normalized()));
}

inline Rigid3d LookDownFrom(const Eigen::Vector3d& center, double yaw) {
  // Camera z down (world -z), x along the yaw direction.
  Eigen::Matrix3d world_from_cam;
  world_from_cam.col(0) = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0);
  world_from_cam.col(2) = -Eigen::Vector3d::UnitZ();
  world_from_cam.col(1) = world_from_cam.col(2).cross(world_from_cam.col(0));
  Rigid3d cam_from_world;
  cam_from_world.rotation = Eigen::Quaterniond(world_from_cam.transpose());
  cam_from_world.translation = -(world_from_cam.transpose() * center);
  return cam_from_world;
}

inline TestScene MakeTestScene(const TestSceneOptions& options) {
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> normal;
  TestScene scene;
  Camera camera;
  camera.camera_id = 1;
  camera.model_id = CameraModelId::kSimpleRadial;
  camera.width = 1024;
  camera.height = 768;
  camera.params = {800.0, 512.0, 384.0, -0.04};
  scene.truth.AddCamera(camera);
  if (options.rig) {
    Camera second = camera;
    second.camera_id = 2;
    scene.truth.AddCamera(second);
    scene.rig.reference_camera_id = 1;
    scene.rig.cameras.push_back({2, options.rig_cam2_from_cam1,
                                 options.rig_rotation_sigma_rad,
                                 options.rig_translation_sigma_m});
  }

  image_t image_id = 1;
  std::vector<int> line_of_image;  // by image_id - 1
  for (int line = 0; line < options.num_lines; ++line) {
    for (int k = 0; k < options.images_per_line; ++k) {
      if (std::find(options.missing_images.begin(),
                    options.missing_images.end(),
                    std::make_pair(line, k)) != options.missing_images.end()) {
        continue;
      }
      TestSceneOptions::Hover hover;
      for (const TestSceneOptions::Hover& h : options.hovers) {
        if (h.line == line && h.index == k) hover = h;
      }
      const double x = (line % 2 == 0 ? k : options.images_per_line - 1 - k) *
                       options.spacing_m;
      // The station's position jitter; a hovering vehicle holds it.
      const Eigen::Vector3d jitter(0.05 * normal(rng), 0.05 * normal(rng),
                                   0.05 * normal(rng));
      for (int h = 0; h < hover.count; ++h) {
        line_of_image.push_back(line);
        Image image;
        image.image_id = image_id++;
        image.camera_id = 1;
        image.name = "img" + std::to_string(image.image_id) + ".png";
        const Eigen::Vector3d center =
            jitter +
            Eigen::Vector3d(
                x + (h - 0.5 * (hover.count - 1)) * hover.spacing_m,
                line * options.line_spacing_m +
                    options.wiggle_m * std::sin(2.0 * M_PI * x / 10.0),
                options.altitude_m +
                    0.4 * options.wiggle_m * std::sin(2.0 * M_PI * x / 13.0));
        image.cam_from_world =
            LookDownFrom(center, 0.05 * normal(rng) + (line % 2) * M_PI);
        scene.truth.AddImage(image);
        if (!options.rig) continue;
        const double time = static_cast<double>(image.image_id);
        scene.image_times[image.image_id] = time;
        const Rigid3d& cam2_from_cam1 = options.rig_cam2_from_cam1;
        Image rig_image = image;
        rig_image.image_id = image_id++;
        rig_image.camera_id = 2;
        rig_image.name = "rig" + std::to_string(rig_image.image_id) + ".png";
        rig_image.cam_from_world.rotation =
            cam2_from_cam1.rotation * image.cam_from_world.rotation;
        rig_image.cam_from_world.translation =
            cam2_from_cam1.rotation * image.cam_from_world.translation +
            cam2_from_cam1.translation;
        scene.truth.AddImage(rig_image);
        scene.image_times[rig_image.image_id] = time;
        line_of_image.push_back(line);
      }
    }
  }

  const double x_max = (options.images_per_line - 1) * options.spacing_m;
  const double y_max = (options.num_lines - 1) * options.line_spacing_m;
  std::uniform_real_distribution<double> ux(-1.0, x_max + 1.0);
  std::uniform_real_distribution<double> uy(-1.0, y_max + 1.0);
  point3D_t point_id = 1;
  for (int p = 0; p < options.num_points; ++p) {
    const double x = ux(rng);
    const double y = uy(rng);
    Point3D point;
    point.point3D_id = point_id;
    point.xyz = Eigen::Vector3d(x, y, 0.3 * std::sin(x) * std::cos(0.7 * y));
    for (Image& image : scene.truth.Images()) {
      const Eigen::Vector3d in_cam = image.cam_from_world * point.xyz;
      if (in_cam.z() <= 0.1) continue;
      const Eigen::Vector2d xy = camera.ImgFromCam(in_cam);
      if (xy.x() < 0 || xy.y() < 0 || xy.x() > camera.width ||
          xy.y() > camera.height) {
        continue;
      }
      Point2D point2D;
      point2D.xy = xy;
      point2D.point3D_id = point.point3D_id;
      point.track.push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back(point2D);
    }
    if (point.track.size() < 2) {
      for (const TrackElement& element : point.track) {
        Image& image = scene.truth.Images()[element.image_id - 1];
        image.points2D.pop_back();
      }
      continue;
    }
    scene.truth.AddPoint3D(point);
    ++point_id;
  }

  scene.observed = scene.truth;
  std::mt19937 attitude_rng(options.seed + 1000);
  std::normal_distribution<double> attitude_normal;
  for (Image& image : scene.observed.Images()) {
    for (Point2D& point2D : image.points2D) {
      point2D.xy +=
          options.pixel_sigma * Eigen::Vector2d(normal(rng), normal(rng));
    }
  }
  for (const Image& image : scene.truth.Images()) {
    if (image.camera_id != 1) continue;
    const int line = line_of_image[image.image_id - 1];
    ImagePosePrior prior;
    prior.image_id = image.image_id;
    prior.dive = line >= options.first_line_of_dive_2 ? 2 : 1;
    prior.position_in_world =
        image.ProjectionCenter() +
        options.nav_sigma_m *
            Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) +
        (prior.dive == 2 ? options.dive2_bias : Eigen::Vector3d::Zero());
    prior.position_covariance =
        options.nav_sigma_m * options.nav_sigma_m * Eigen::Matrix3d::Identity();
    const Eigen::Vector3d w = options.attitude_sigma_rad *
                              Eigen::Vector3d(attitude_normal(attitude_rng),
                                              attitude_normal(attitude_rng),
                                              attitude_normal(attitude_rng));
    // world_from_cam_prior = Exp(w) world_from_cam: noise in the world frame.
    prior.cam_from_world_rotation =
        image.cam_from_world.rotation * RotationFromVector(w).conjugate();
    prior.rotation_covariance = options.attitude_sigma_rad *
                                options.attitude_sigma_rad *
                                Eigen::Matrix3d::Identity();
    scene.priors.push_back(prior);
  }
  return scene;
}

// Adjustment options for the test scenes: intrinsics fixed at the truth,
// one thread (deterministic).
inline NavBundleAdjustmentOptions FixedIntrinsics() {
  NavBundleAdjustmentOptions options;
  options.refine_focal_length = false;
  options.refine_extra_params = false;
  options.num_threads = 1;
  return options;
}

// Moves every pose and point of `model` by small random amounts (an
// imperfect starting model).
inline void Perturb(double position_sigma_m, double angle_sigma_rad,
                    unsigned seed, Reconstruction* model) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const auto random3 = [&] {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  };
  for (Image& image : model->Images()) {
    const Eigen::Vector3d center =
        image.ProjectionCenter() + position_sigma_m * random3();
    const Eigen::Vector3d w = angle_sigma_rad * random3();
    image.cam_from_world.rotation =
        image.cam_from_world.rotation * RotationFromVector(w);
    image.cam_from_world.translation =
        -(image.cam_from_world.rotation * center);
  }
  for (Point3D& point : model->Points3D()) {
    point.xyz += position_sigma_m * random3();
  }
}

// RMS distance between the camera centres of two models with the same ids.
inline double CameraCenterRmse(const Reconstruction& a,
                               const Reconstruction& b) {
  double sum = 0.0;
  for (const Image& image : a.Images()) {
    sum += (image.ProjectionCenter() -
            b.FindImage(image.image_id)->ProjectionCenter())
               .squaredNorm();
  }
  return std::sqrt(sum / a.Images().size());
}

}  // namespace uw::test
