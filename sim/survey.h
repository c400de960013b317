// Survey trajectories over a synthetic world: where the vehicle is when each
// image is taken, and how the camera sits on the vehicle.
//
// Frames: world = the world's local East-North-Up frame (metres, z up).
// Vehicle body frame: x forward, y left, z up. Camera frame: COLMAP's
// (x right, y down, z forward). Vehicle attitude as roll, pitch, yaw with
// world_from_vehicle = Rz(yaw) * Ry(pitch) * Rx(roll), yaw counter-clockwise
// from east (docs/uwsim.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "colmap_plugins/nav/attitude.h"
#include "colmap_plugins/nav/camera_mount.h"
#include "colmap_plugins/scene/model.h"

namespace uw::sim {

struct World;

enum class SurveyKind {
  kLawnmower,   // overlapping back-and-forth passes over the survey area
  kSinglePass,  // one long sequential pass along the survey axis (doming)
  kMultiDive,   // lawnmowers over overlapping parts of the area, crossing
  kVideo,       // frames at a fixed rate along a continuous lawnmower track
  kViews,       // a pitch x roll grid of views of one surface point (thesis)
};
std::string SurveyKindName(SurveyKind kind);
SurveyKind SurveyKindFromName(const std::string& name);  // throws uw::Error

struct SurveyOptions {
  // Camera stand-off from the survey plane (altitude over a floor, range to
  // a wall), metres.
  double distance_m = 2.5;
  // Overlap of consecutive images along a pass and of neighbouring passes,
  // as fractions of the image footprint.
  double forward_overlap = 0.75;
  double side_overlap = 0.5;
  // Fraction of the world's survey extent covered (centred), per axis. The
  // defaults give a small survey (~30 images of the default seafloor) that
  // stock colmap reconstructs in a few minutes on 2 cores; 75 % forward
  // overlap leaves half of each image in three consecutive ones, which
  // colmap's incremental mapper needs to chain a pass reliably.
  double coverage_along = 0.35;
  double coverage_across = 0.45;
  double speed_m_per_s = 0.5;
  // Vehicle motion noise: standard deviations of roll/pitch/yaw (deg) and
  // of the position (m) around the nominal track.
  double attitude_jitter_deg = 2.0;
  double position_jitter_m = 0.05;
  // Camera on the vehicle: lever arm (vehicle frame, m) and boresight
  // (small rotation from the nominal mount, roll/pitch/yaw in deg).
  Eigen::Vector3d lever_arm_m = Eigen::Vector3d(0.6, 0.0, -0.3);
  Eigen::Vector3d boresight_deg = Eigen::Vector3d(0.3, -0.5, 0.8);
  // 0: no limit; otherwise the survey stops after this many images.
  int max_images = 0;

  // multi_dive: the survey area is cut along its longer axis into
  // num_dives parts, each sharing dive_overlap of its area with the next;
  // dive 1 flies its lines along the survey axis, dive 2 across it (at
  // 90 deg), dive 3 along again, ... A dive starts dive_gap_s after the
  // last image of the one before.
  int num_dives = 2;
  double dive_overlap = 0.4;
  double dive_gap_s = 3600.0;

  // video: frames every 1 / frame_rate_hz seconds along a continuous
  // lawnmower track over the survey area: lines joined by half-circle turns
  // (floor) or by vertical moves (wall; the vehicle reverses along the wall
  // to keep its camera on it). Frames of a turn carry the pass of the line
  // they leave; the jitter above is drawn afresh for every frame.
  double frame_rate_hz = 2.0;

  // views: the camera at views_distance_m from a surface point, its
  // principal ray through the point, tilted by every pitch and roll of
  // -views_max_angle_deg, ..., +views_max_angle_deg in views_step_deg steps
  // (17 x 17 = 289 views by default, as in the thesis). At pitch = roll = 0
  // the optical axis is anti-parallel to the surface normal at the point:
  // the area-weighted mean normal of the triangles whose centroids lie
  // within views_normal_radius_m of it and that face the survey side (a
  // plane fitted to the scene around the point, not the facet it falls
  // on). Pitch turns the camera about its -x axis, roll about its -y axis,
  // applied in that order to the 0/0 view: with the down-looking mount on
  // a level floor they are the vehicle's pitch and roll. Views are taken
  // pitch by pitch (station.pass = pitch index), roll back and forth.
  // The point is views_target (world frame) if set, otherwise the first
  // surface met coming from the water along the line through the world's
  // survey_origin along survey_normal (the floor under or over a
  // seafloor's mean height, the top of the vent). The grid is exact
  // unless views_jitter applies the vehicle jitter above.
  double views_distance_m = 3.0;
  double views_max_angle_deg = 40.0;
  double views_step_deg = 5.0;
  double views_normal_radius_m = 0.5;
  std::optional<Eigen::Vector3d> views_target;
  bool views_jitter = false;

  void Check() const;
};
void to_json(nlohmann::json& json, const SurveyOptions& options);
void from_json(const nlohmann::json& json, SurveyOptions& options);

struct SurveyStation {
  // "00000", "00001", ... in survey order; the writer adds the extension.
  std::string image_name;
  double time_s = 0.0;
  int dive = 1;
  int pass = 0;  // index of the pass (line) this image belongs to
  // True vehicle attitude (radians) and position.
  Eigen::Vector3d vehicle_rpy = Eigen::Vector3d::Zero();
  Eigen::Vector3d vehicle_position = Eigen::Vector3d::Zero();
  Rigid3d cam_from_world;
};

// The vehicle attitude is nav.csv's roll, pitch, yaw, as the importer of
// navigation reads it.
using uw::RollPitchYawFromRotation;
using uw::WorldFromVehicleRotation;

// The camera's pose on the vehicle: the importer's mount "down" over a
// floor, "starboard" (vehicle −y) at a wall (a survey plane steeper than
// ~45°), with the lever arm and boresight of `options`
// (colmap_plugins/nav/camera_mount.h).
Rigid3d VehicleFromCam(const World& world, const SurveyOptions& options);
// That nominal mount alone (truth/sim.json's truth.camera_mount, so that
// scripts import the log as uwsim mounted the camera).
CameraMount SurveyCameraMount(const World& world);

// Plans the stations of a survey of `world` seen through `camera`. The
// image footprint, and so the spacing, follows from the camera's focal
// length and size at the stand-off distance. Deterministic for a seed.
// Throws uw::Error for views whose target cannot be found on the mesh or
// whose vehicle attitude would pitch beyond 85 deg.
std::vector<SurveyStation> PlanSurvey(SurveyKind kind, const World& world,
                                      const Camera& camera,
                                      const SurveyOptions& options,
                                      uint64_t seed);

}  // namespace uw::sim
