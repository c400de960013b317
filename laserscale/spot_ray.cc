#include "laserscale/spot_ray.h"

#include <sstream>

#include "colmap_plugins/cameras/camera_models.h"

namespace uw {

SpotHit CastSpot(const RayCaster& caster, const Camera& camera,
                 const Rigid3d& cam_from_world,
                 const Eigen::Vector2d& spot_px) {
  const auto no_hit = [](const std::string& problem) {
    return SpotHit{std::nullopt, problem};
  };
  if (!spot_px.allFinite()) return no_hit("the spot is not finite");
  if (spot_px.x() < 0.0 || spot_px.y() < 0.0 ||
      spot_px.x() > static_cast<double>(camera.width) ||
      spot_px.y() > static_cast<double>(camera.height)) {
    std::ostringstream message;
    message << "the spot (" << spot_px.x() << ", " << spot_px.y()
            << ") px lies outside the " << camera.width << "x" << camera.height
            << " image";
    return no_hit(message.str());
  }
  const Eigen::Vector3d ray_in_cam =
      CameraModelCamFromImg(camera.model_id, camera.params.data(), spot_px);
  if (!ray_in_cam.allFinite() ||
      (camera.ImgFromCam(ray_in_cam) - spot_px).norm() > 1e-6) {
    return no_hit("the camera model cannot unproject the spot");
  }
  const Rigid3d world_from_cam = cam_from_world.Inverse();
  const Eigen::Vector3d direction =
      (world_from_cam.RotationMatrix() * ray_in_cam).normalized();
  const std::optional<RayCaster::Hit> hit =
      caster.Intersect(world_from_cam.translation, direction);
  if (!hit) return no_hit("the ray through the spot meets no surface");
  return {hit->point_in_world, ""};
}

}  // namespace uw
