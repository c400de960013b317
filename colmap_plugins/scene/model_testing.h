// For tests that build small models by hand.
#pragma once

#include "colmap_plugins/scene/model.h"

namespace uw {

// A square pinhole camera, principal point at the centre.
inline Camera TestPinholeCamera(camera_t camera_id, uint64_t size_px,
                                double focal_px) {
  Camera camera;
  camera.camera_id = camera_id;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = size_px;
  camera.height = size_px;
  const double centre = 0.5 * static_cast<double>(size_px);
  camera.params = {focal_px, focal_px, centre, centre};
  return camera;
}

}  // namespace uw
