#include "colmap_plugins/nav/camera_mount.h"

#include <cmath>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "colmap_plugins/nav/attitude.h"
#include "common/util/error.h"
#include "common/util/time_text.h"

namespace uw {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

constexpr CameraMount kMounts[] = {CameraMount::kDown, CameraMount::kStarboard,
                                   CameraMount::kPort, CameraMount::kForward};

// The camera's x (right), y (down) and z (optical axis) in the vehicle frame.
Eigen::Matrix3d Axes(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                     const Eigen::Vector3d& z) {
  Eigen::Matrix3d vehicle_from_cam;
  vehicle_from_cam << x, y, z;
  return vehicle_from_cam;
}

}  // namespace

std::string CameraMountName(CameraMount mount) {
  switch (mount) {
    case CameraMount::kDown:
      return "down";
    case CameraMount::kStarboard:
      return "starboard";
    case CameraMount::kPort:
      return "port";
    case CameraMount::kForward:
      return "forward";
  }
  throw ErrorAt("invalid CameraMount ", static_cast<int>(mount));
}

CameraMount CameraMountFromName(const std::string& name) {
  std::string available;
  for (const CameraMount mount : kMounts) {
    if (name == CameraMountName(mount)) return mount;
    available += (available.empty() ? "" : ", ") + CameraMountName(mount);
  }
  throw ErrorAt("unknown camera mount '", name, "' (available: ", available,
                ")");
}

Eigen::Matrix3d NominalVehicleFromCamRotation(CameraMount mount) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  // Each camera x = camera y × camera z, so every matrix is a rotation.
  switch (mount) {
    case CameraMount::kDown:  // image top towards the bow
      return Axes(-y, -x, -z);
    case CameraMount::kStarboard:  // image upright, right towards the stern
      return Axes(-x, -z, -y);
    case CameraMount::kPort:  // image upright, right towards the bow
      return Axes(x, -z, y);
    case CameraMount::kForward:  // image upright, right to starboard
      return Axes(-y, -z, x);
  }
  throw ErrorAt("invalid CameraMount ", static_cast<int>(mount));
}

void NavToCameraOptions::Check() const {
  if (!lever_arm_m.allFinite()) {
    throw ErrorAt("lever arm (", lever_arm_m.transpose(), ") m must be finite");
  }
  if (!boresight_deg.allFinite()) {
    throw ErrorAt("boresight (", boresight_deg.transpose(),
                  ") deg must be finite");
  }
  if (!std::isfinite(time_offset_s)) {
    throw ErrorAt("time offset ", SecondsText(time_offset_s),
                  " s must be finite");
  }
  if (!(unlogged_roll_pitch_sigma_deg > 0.0 &&
        std::isfinite(unlogged_roll_pitch_sigma_deg))) {
    throw ErrorAt("--unlogged_roll_pitch_sigma ", unlogged_roll_pitch_sigma_deg,
                  " deg must be > 0");
  }
}

Rigid3d VehicleFromCam(const NavToCameraOptions& options) {
  options.Check();
  const Eigen::Matrix3d boresight =
      WorldFromVehicleRotation(options.boresight_deg * kDegToRad);
  Rigid3d vehicle_from_cam;
  vehicle_from_cam.rotation = Eigen::Quaterniond(
      NominalVehicleFromCamRotation(options.mount) * boresight);
  vehicle_from_cam.translation = options.lever_arm_m;
  return vehicle_from_cam;
}

std::string DescribeNavToCamera(const NavToCameraOptions& options) {
  const Eigen::Vector3d& lever = options.lever_arm_m;
  const Eigen::Vector3d& boresight = options.boresight_deg;
  return fmt::format(
      "mount {}, lever arm {:g},{:g},{:g} m, boresight {:g},{:g},{:g} deg, "
      "time offset {} s",
      CameraMountName(options.mount), lever.x(), lever.y(), lever.z(),
      boresight.x(), boresight.y(), boresight.z(),
      SecondsText(options.time_offset_s));
}

}  // namespace uw
