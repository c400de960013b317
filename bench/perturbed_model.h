// A COLMAP model moved away from its bundle-adjustment optimum, so that a
// bundle adjuster has work to do. A mapper's model is already adjusted:
// adjusting it again moves nothing, and any adjuster, even one that does
// nothing, "reaches" the optimum. Shared by the comparison of our bundle
// adjuster with colmap's (tests/compare_with_colmap_test.cc) and its timing
// (bench/ba_speed_bench.cc).
#pragma once

#include <algorithm>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

#include "colmap_plugins/cameras/camera_models.h"
#include "colmap_plugins/scene/model.h"

namespace uw::bench {

struct PerturbationOptions {
  // Gaussian noise on each camera centre (per axis, as a fraction of the
  // diagonal of the box around the centres) and on each camera's rotation
  // (per axis of the rotation vector).
  double centre_sigma_fraction = 0.005;
  double rotation_sigma_deg = 0.2;
  // Every focal length is multiplied by this.
  double focal_length_factor = 1.02;
  unsigned seed = 1;
};

// Perturbs the cameras of a COLMAP 3.x layout model (no frames); 3D points
// and observations stay as they are.
inline void PerturbModel(const PerturbationOptions& options,
                         Reconstruction* model) {
  if (!model->Frames().empty()) {
    throw std::invalid_argument(
        "PerturbModel: models with frames (COLMAP "
        "4.x layout) are not supported");
  }
  Eigen::AlignedBox3d box;
  for (const Image& image : model->Images())
    box.extend(image.ProjectionCenter());
  const double centre_sigma =
      options.centre_sigma_fraction * box.diagonal().norm();
  const double rotation_sigma = options.rotation_sigma_deg * M_PI / 180.0;
  std::mt19937 rng(options.seed);
  std::normal_distribution<double> normal;
  const auto noise = [&](double sigma) -> Eigen::Vector3d {
    return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * sigma;
  };
  for (Image& image : model->Images()) {
    const Eigen::Vector3d centre =
        image.ProjectionCenter() + noise(centre_sigma);
    const Eigen::Vector3d rotation_vector = noise(rotation_sigma);
    const Eigen::Quaterniond cam_from_world =
        (image.cam_from_world.rotation.normalized() *
         Eigen::Quaterniond(Eigen::AngleAxisd(rotation_vector.norm(),
                                              rotation_vector.normalized())))
            .normalized();
    image.cam_from_world.rotation = cam_from_world;
    image.cam_from_world.translation = -(cam_from_world * centre);
  }
  for (Camera& camera : model->Cameras()) {
    VisitCameraModel(camera.model_id, [&](auto tag) {
      using CameraModel = typename decltype(tag)::type;
      for (const int index : CameraModel::kFocalLengthIdxs) {
        camera.params[index] *= options.focal_length_factor;
      }
    });
  }
}

}  // namespace uw::bench
