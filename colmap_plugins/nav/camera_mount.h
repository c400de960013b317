// How a camera sits on the vehicle: a nominal mount (down, starboard, port,
// forward), a small boresight rotation after it and a lever arm. Frames:
// vehicle x forward, y left, z up (nav.csv); camera COLMAP's (x right,
// y down, z forward). uwsim places its cameras with the same definitions.
#pragma once

#include <string>

#include <Eigen/Core>

#include "colmap_plugins/scene/model.h"

namespace uw {

enum class CameraMount {
  kDown,       // looking down, image top towards the bow
  kStarboard,  // looking to starboard (vehicle -y), image upright
  kPort,       // looking to port (vehicle +y), image upright
  kForward,    // looking ahead (vehicle +x), image upright
};
std::string CameraMountName(CameraMount mount);  // "down", "starboard", ...
// Throws uw::Error listing the names.
CameraMount CameraMountFromName(const std::string& name);

// Rotation vehicle_from_cam of the nominal mount: its columns are the
// camera's axes in the vehicle frame.
Eigen::Matrix3d NominalVehicleFromCamRotation(CameraMount mount);

// Everything that turns a navigation record (vehicle pose at a time) into
// the pose of a camera.
struct NavToCameraOptions {
  CameraMount mount = CameraMount::kDown;
  // The camera centre in the vehicle frame, m.
  Eigen::Vector3d lever_arm_m = Eigen::Vector3d::Zero();
  // Roll, pitch, yaw (deg) of a small rotation after the mount, about the
  // camera's own axes: vehicle_from_cam = mount * Rz(yaw) Ry(pitch)
  // Rx(roll), so roll turns about the camera's x (right), pitch about its y
  // (down) and yaw about its optical axis (uwsim's survey_options).
  Eigen::Vector3d boresight_deg = Eigen::Vector3d::Zero();
  // The navigation time at which an image was taken = its time (from
  // image_times.csv or its nav.csv row) + time_offset_s: e.g. +0.2 when the
  // camera's time stamps run 0.2 s behind the navigation's clock.
  double time_offset_s = 0.0;
  // The sigma (deg) of the roll and pitch taken as 0 for a log that has
  // yaw but no roll and pitch: how far a vehicle rolls and pitches in
  // survey, carried through the lever arm into the camera's position.
  double unlogged_roll_pitch_sigma_deg = 5.0;

  // Throws uw::Error on non-finite values and a sigma <= 0.
  void Check() const;
};

// vehicle_from_cam: rotation mount * boresight, translation lever_arm_m.
Rigid3d VehicleFromCam(const NavToCameraOptions& options);

// One line: "mount down, lever arm 0.6,0,-0.3 m, boresight 0,0,0 deg, time
// offset 0 s" (what pose_prior_importer prints and ba_report.json stores).
std::string DescribeNavToCamera(const NavToCameraOptions& options);

}  // namespace uw
