// Which images of a model see a point of a surface: in front of the camera,
// inside the image where the camera model is invertible, and with nothing
// of the surface in between. uwsim observes its true surface with it, and
// model_comparer measures which part of the true surface a survey saw.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"

namespace uw {

struct SurfaceObservation {
  size_t view = 0;  // index into the model's Images()
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // COLMAP convention
};

// Keeps references to the model and the caster, which must outlive it.
// Thread-safe for concurrent queries.
class SurfaceVisibility {
 public:
  // Throws uw::Error for an image whose camera is not in the model.
  SurfaceVisibility(const Reconstruction& model, const RayCaster& caster);

  size_t NumViews() const { return views_.size(); }

  // The pixel of the point in image `view` if it is in view (no occlusion
  // test). A polynomial distortion folds rays from far outside the field of
  // view back into the image; the round trip through the inverse rejects
  // them.
  std::optional<Eigen::Vector2d> PixelInView(
      size_t view, const Eigen::Vector3d& point_in_world) const;

  // The images that see a point on the surface: in view and nothing in
  // front of it along the ray from the camera centre.
  std::vector<SurfaceObservation> Observe(
      const Eigen::Vector3d& point_in_world) const;

 private:
  struct View {
    const Camera* camera;
    Eigen::Matrix3d cam_from_world_rotation;
    Eigen::Vector3d cam_from_world_translation;
    Eigen::Vector3d centre_in_world;
  };

  std::vector<View> views_;
  const RayCaster& caster_;
};

}  // namespace uw
