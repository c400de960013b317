#include "colmap_plugins/scene/model_stats.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace uw {

ModelStats ComputeModelStats(const Reconstruction& reconstruction) {
  ModelStats stats;
  stats.num_cameras = reconstruction.Cameras().size();
  // A model file lists registered images only, so both counts are the same,
  // exactly as COLMAP reports them after reading a model.
  stats.num_images = reconstruction.Images().size();
  stats.num_reg_images = reconstruction.Images().size();
  stats.num_points3D = reconstruction.Points3D().size();
  for (const Image& image : reconstruction.Images()) {
    stats.num_observations += image.NumPoints3D();
  }
  if (stats.num_points3D > 0) {
    stats.mean_track_length =
        stats.num_observations / static_cast<double>(stats.num_points3D);
  }
  if (stats.num_reg_images > 0) {
    stats.mean_observations_per_image =
        stats.num_observations / static_cast<double>(stats.num_reg_images);
  }
  double error_sum = 0.0;
  size_t num_errors = 0;
  for (const Point3D& point3D : reconstruction.Points3D()) {
    if (point3D.HasError()) {
      error_sum += point3D.error;
      ++num_errors;
    }
  }
  if (num_errors > 0) stats.mean_reprojection_error = error_sum / num_errors;
  return stats;
}

std::string FormatModelAnalyzerReport(const ModelStats& stats) {
  return fmt::format(
      "Cameras: {}\n"
      "Images: {}\n"
      "Registered images: {}\n"
      "Points: {}\n"
      "Observations: {}\n"
      "Mean track length: {:f}\n"
      "Mean observations per image: {:f}\n"
      "Mean reprojection error: {:f}px\n",
      stats.num_cameras, stats.num_images, stats.num_reg_images,
      stats.num_points3D, stats.num_observations, stats.mean_track_length,
      stats.mean_observations_per_image, stats.mean_reprojection_error);
}

ReprojectionErrors RecomputeReprojectionErrors(
    const Reconstruction& reconstruction) {
  ReprojectionErrors errors;
  double point_error_sum = 0.0;
  size_t num_points = 0;
  double observation_error_sum = 0.0;
  for (const Point3D& point3D : reconstruction.Points3D()) {
    double track_error_sum = 0.0;
    size_t track_count = 0;
    for (const TrackElement& element : point3D.track) {
      const Image& image = *reconstruction.FindImage(element.image_id);
      const Camera& camera = *reconstruction.FindCamera(image.camera_id);
      const Eigen::Vector3d point_in_cam = image.cam_from_world * point3D.xyz;
      ++errors.num_observations;
      if (point_in_cam.z() < std::numeric_limits<double>::epsilon()) {
        ++errors.num_behind_camera;
        continue;
      }
      const double error = (camera.ImgFromCam(point_in_cam) -
                            image.points2D[element.point2D_idx].xy)
                               .norm();
      track_error_sum += error;
      observation_error_sum += error;
      ++track_count;
    }
    if (track_count == 0) continue;
    const double point_error = track_error_sum / track_count;
    point_error_sum += point_error;
    ++num_points;
    if (point3D.HasError()) {
      errors.max_stored_error_difference =
          std::max(errors.max_stored_error_difference,
                   std::abs(point_error - point3D.error));
    }
  }
  const size_t num_valid = errors.num_observations - errors.num_behind_camera;
  if (num_points > 0) errors.mean_point_error = point_error_sum / num_points;
  if (num_valid > 0) {
    errors.mean_observation_error = observation_error_sum / num_valid;
  }
  return errors;
}

}  // namespace uw
