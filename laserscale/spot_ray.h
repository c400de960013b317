// Where a detected laser spot lies on a model's surface: the ray from the
// camera centre through the spot (undistorted by the image's COLMAP camera
// model, which absorbs the port's refraction, ch4 spec §2.1), cast onto the
// model's mesh; the first surface it meets (§2.3).
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"
#include "common/mesh/ray_caster.h"

namespace uw {

struct SpotHit {
  std::optional<Eigen::Vector3d> point_in_world;  // model units and frame
  std::string problem;  // why there is no hit; empty with one
};

// `spot_px` in COLMAP's pixel convention (upper-left corner (0, 0)). No hit,
// with the reason, for a non-finite spot, one outside the image, one the
// camera model cannot unproject (the ray does not project back onto it to
// 1e-6 px: beyond a fisheye's 90 degrees or where a distortion folds), or a
// ray that meets no surface.
SpotHit CastSpot(const RayCaster& caster, const Camera& camera,
                 const Rigid3d& cam_from_world, const Eigen::Vector2d& spot_px);

}  // namespace uw
