#include "laserscale/beam_image.h"

#include <algorithm>
#include <limits>

#include "colmap_plugins/cameras/camera_models.h"

namespace uw::lsd {
namespace {

// Points along each beam for its image (distortion bends it).
constexpr int kBeamSamples = 64;

}  // namespace

std::vector<Eigen::Vector2d> BeamImage(const Camera& camera, const Laser& laser,
                                       const SpotDetectorOptions& options) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= kBeamSamples; ++i) {
    const double z =
        options.min_range_m +
        (options.max_range_m - options.min_range_m) * i / kBeamSamples;
    const Eigen::Vector3d point_in_cam =
        laser.origin_in_cam + (z - laser.origin_in_cam.z()) /
                                  laser.direction_in_cam.z() *
                                  laser.direction_in_cam;
    const Eigen::Vector2d pixel = CameraModelImgFromCam(
        camera.model_id, camera.params.data(), point_in_cam);
    if (!pixel.allFinite()) continue;
    const Eigen::Vector3d ray =
        CameraModelCamFromImg(camera.model_id, camera.params.data(), pixel);
    if ((ray.head<2>() - point_in_cam.head<2>() / point_in_cam.z()).norm() >
        1e-6) {
      continue;
    }
    points.push_back(pixel);
  }
  return points;
}

double DistanceToPolyline(const Eigen::Vector2d& p,
                          const std::vector<Eigen::Vector2d>& line) {
  double best = std::numeric_limits<double>::infinity();
  if (line.size() == 1) return (p - line[0]).norm();
  for (size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d d = line[i] - line[i - 1];
    const double length2 = d.squaredNorm();
    const double t =
        length2 > 0.0 ? std::clamp((p - line[i - 1]).dot(d) / length2, 0.0, 1.0)
                      : 0.0;
    best = std::min(best, (p - (line[i - 1] + t * d)).norm());
  }
  return best;
}

Eigen::Vector2d DirectionNear(const std::vector<Eigen::Vector2d>& line,
                              const Eigen::Vector2d& p) {
  Eigen::Vector2d best = Eigen::Vector2d::UnitX();
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d d = line[i] - line[i - 1];
    if (d.squaredNorm() == 0.0) continue;
    const double t =
        std::clamp((p - line[i - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double distance = (p - (line[i - 1] + t * d)).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best = d.normalized();
    }
  }
  return best;
}

bool OnOwnBeam(const Eigen::Vector2d& p,
               const std::vector<std::vector<Eigen::Vector2d>>& beams,
               size_t own, double max_distance) {
  const double distance = DistanceToPolyline(p, beams[own]);
  if (distance > max_distance) return false;
  for (size_t l = 0; l < beams.size(); ++l) {
    if (l != own && !beams[l].empty() &&
        DistanceToPolyline(p, beams[l]) < distance) {
      return false;
    }
  }
  return true;
}

}  // namespace uw::lsd
