// Which way is up in a model whose frame is its own: a stock COLMAP model
// has an arbitrary rotation (its +z often points into the seabed), so a
// top view or a height ramp must find "up" from the cameras themselves. A
// survey vehicle turns about the vertical (its heading changes between
// passes) and hardly rolls or pitches, so the cameras' turns share that
// axis; its sign is where the cameras look (down at a floor) or hold their
// images' down (upright at a wall).
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct CameraUp {
  Eigen::Vector3d up_in_model = Eigen::Vector3d::UnitZ();  // unit
  // How it was found, for the report: "the axis the cameras turn about",
  // or, for cameras that do not turn, "assumed: the cameras look down
  // (...)" or "the images' up (they do not turn)".
  std::string method;
  // How much the cameras agree: the share of their turns about that axis,
  // or the length of the mean unit direction used; 0 (none) to 1.
  double agreement = 0.0;
};

// Up as the axis the cameras turn about when one of them turns by more
// than 20 deg from the first and 80 % of the squared turn angles lie about
// one axis, signed so that the mean optical axis plus the mean image-down
// axis (camera +y) points down (nullopt when that sum is shorter than 0.5
// along it). Cameras that do not turn cannot tell a floor from a wall: up
// is then minus the mean optical axis when it is longer than 0.5 (assumed
// to look down, and said so: wrong by 90 deg at a wall surveyed without
// turning, e.g. uwsim's scarp), else minus the mean image-down axis when
// that is. nullopt also for a model without images.
std::optional<CameraUp> UpFromCameras(const Reconstruction& model);

// A rotation that takes `up` to +z and keeps the model's x axis (or, when
// that is nearly up, its y axis) in the x-z plane: a right-handed top view,
// never a mirror image.
Eigen::Matrix3d ViewFromModel(const Eigen::Vector3d& up_in_model);

}  // namespace uw
