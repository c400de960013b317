#include "colmap_plugins/align/visibility.h"

#include "common/util/error.h"

namespace uw {

SurfaceVisibility::SurfaceVisibility(const Reconstruction& model,
                                     const RayCaster& caster)
    : caster_(caster) {
  for (const Image& image : model.Images()) {
    const Camera* camera = model.FindCamera(image.camera_id);
    if (camera == nullptr) {
      throw ErrorAt("image ", image.name, " has unknown camera ",
                    image.camera_id);
    }
    views_.push_back({camera, image.cam_from_world.RotationMatrix(),
                      image.cam_from_world.translation,
                      image.ProjectionCenter()});
  }
}

std::optional<Eigen::Vector2d> SurfaceVisibility::PixelInView(
    size_t view, const Eigen::Vector3d& point_in_world) const {
  const View& v = views_[view];
  const Eigen::Vector3d point_in_cam =
      v.cam_from_world_rotation * point_in_world + v.cam_from_world_translation;
  if (!(point_in_cam.z() > 0.0)) return std::nullopt;
  const Camera& camera = *v.camera;
  const Eigen::Vector2d pixel = camera.ImgFromCam(point_in_cam);
  if (!(pixel.x() >= 0.0 && pixel.y() >= 0.0 &&
        pixel.x() < static_cast<double>(camera.width) &&
        pixel.y() < static_cast<double>(camera.height))) {
    return std::nullopt;
  }
  const Eigen::Vector3d ray =
      CameraModelCamFromImg(camera.model_id, camera.params.data(), pixel);
  constexpr double kMaxRoundTripError = 1e-6;  // normalised image units
  if (!((ray.head<2>() - point_in_cam.head<2>() / point_in_cam.z()).norm() <
        kMaxRoundTripError)) {
    return std::nullopt;
  }
  return pixel;
}

std::vector<SurfaceObservation> SurfaceVisibility::Observe(
    const Eigen::Vector3d& point_in_world) const {
  // A ray towards a surface point stops at that point to within the
  // single-precision resolution of the mesh, possibly on a neighbouring
  // triangle through the same place.
  const double tolerance = 4.0 * caster_.SurfaceEpsilon();
  std::vector<SurfaceObservation> observations;
  for (size_t k = 0; k < views_.size(); ++k) {
    const std::optional<Eigen::Vector2d> pixel = PixelInView(k, point_in_world);
    if (!pixel.has_value()) continue;
    const Eigen::Vector3d offset = point_in_world - views_[k].centre_in_world;
    const double distance = offset.norm();
    const std::optional<RayCaster::Hit> hit = caster_.Intersect(
        views_[k].centre_in_world, offset / distance, distance + tolerance);
    if (hit.has_value() && hit->distance >= distance - tolerance) {
      observations.push_back({k, *pixel});
    }
  }
  return observations;
}

}  // namespace uw
