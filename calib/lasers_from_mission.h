// uwcalib lasers-from-mission's method (thesis ch. 6 §6.6,
// docs/uwcalib.md): every laser of the a-priori set-ups calibrated from the
// spots of the laser images localized against ONE model
// (calib/laser_mission_calibration.h), after checking that the poses and
// the mesh are that model's (calib/same_model_check.h); and the report of
// each spot.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calib/laser_mission_calibration.h"
#include "common/mesh/ray_caster.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spots_io.h"

namespace uw {

// What the laser images gave: their poses in the model (poses.json), their
// spots (spots.json) and the dive of each (others are dive 1).
struct MissionObservations {
  std::vector<LocalizedImage> poses;
  std::vector<ImageSpots> spots;
  std::map<std::string, int> dives;
};

// The spots of laser `laser` that were detected and stable, in the images
// that were localized, with their camera, pose and dive; images of set-up
// `setup` only, unless `any_setup` (one set-up takes every image).
std::vector<MissionSpot> GatherMissionSpots(
    const MissionObservations& observations, const std::string& setup,
    bool any_setup, const std::string& laser);

struct LasersFromMission {
  // The a-priori set-ups, each laser's direction and its covariance
  // calibrated (origins kept).
  std::vector<LaserSetup> setups;
  // uwmetric-lasers-from-mission version 1: per laser the result and every
  // spot's point, dive, inlier flag and problem.
  nlohmann::json report;
};

// Told as each laser is done, for the program to print: its spots before
// the calibration, its result after.
struct LasersFromMissionCallbacks {
  std::function<void(const std::string& setup, const std::string& laser,
                     size_t num_spots)>
      spots_gathered;
  std::function<void(const std::string& setup,
                     const MissionLaserCalibration& result, size_t num_spots)>
      laser_calibrated;
};

// Calibrates every laser of `a_priori` on `caster` (the model's surface).
// Throws uw::Error as CalibrateLaserFromMission, naming the laser, and as
// LaserSetup::Check.
LasersFromMission CalibrateLasersFromMission(
    std::vector<LaserSetup> a_priori, const RayCaster& caster,
    const MissionObservations& observations,
    const MissionCalibrationOptions& options,
    const LasersFromMissionCallbacks& callbacks = {});

// The files uwcalib lasers-from-mission reads.
struct LasersFromMissionOptions {
  std::string input_path;        // COLMAP model the images were localized in
  std::string mesh_path;         // that model's surface (PLY or OBJ)
  std::string spots_path;        // spots.json (laserscale detect)
  std::string poses_path;        // poses.json (laserscale localize)
  std::string origins_path;      // lasers.json with the known origins
  std::string image_dives_path;  // image_name,dive; empty: all dive 1
  MissionCalibrationOptions calibration;

  // Throws uw::Error naming the first bad field.
  void Check() const;
};

// Reads the files and calibrates. Refuses (uw::Error naming the files)
// poses localized against another model and a mesh that is not the
// surface of theirs: points of two scales must never meet in one line.
LasersFromMission CalibrateLasersFromMissionFiles(
    const LasersFromMissionOptions& options,
    const LasersFromMissionCallbacks& callbacks = {});

// One line of uwcalib lasers-from-mission's output for a laser: inliers of
// the num_spots, depths, direction, its sigma and angle from the a-priori
// one, the image-line RMS overall and per dive.
std::string DescribeMissionLaser(const std::string& setup,
                                 const MissionLaserCalibration& result,
                                 size_t num_spots);

}  // namespace uw
