#include "calib/lasers_from_mission.h"

#include <fmt/format.h>

#include "calib/image_dives.h"
#include "calib/same_model_check.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/mesh/mesh.h"
#include "common/util/json_fields.h"

namespace uw {
namespace {

nlohmann::json LaserReport(const Laser& laser,
                           const std::vector<MissionSpot>& spots,
                           const MissionLaserCalibration& result) {
  nlohmann::json by_dive = nlohmann::json::array();
  for (const auto& dive : result.rms_by_dive) {
    by_dive.push_back({{"dive", dive.dive},
                       {"num_spots", dive.num_spots},
                       {"rms_px", dive.rms_px}});
  }
  nlohmann::json spot_reports = nlohmann::json::array();
  for (size_t k = 0; k < spots.size(); ++k) {
    const Eigen::Vector3d& p = result.points_in_cam[k];
    spot_reports.push_back({{"image", spots[k].image},
                            {"dive", spots[k].dive},
                            {"point_in_cam", ToJson(p)},
                            {"inlier", static_cast<bool>(result.inliers[k])},
                            {"problem", result.problems[k]}});
  }
  return {{"laser", LaserJson(laser)},
          {"num_spots", spots.size()},
          {"num_inliers", result.num_inliers},
          {"depth_range_model_units", {result.min_depth, result.max_depth}},
          {"sigma_deg", result.sigma_deg},
          {"angle_from_a_priori_deg", result.angle_from_a_priori_deg},
          {"monte_carlo_iterations", result.num_iterations_used},
          {"image_line_rms_px", result.rms_px},
          {"image_line_rms_by_dive", by_dive},
          {"spots", spot_reports}};
}

}  // namespace

std::vector<MissionSpot> GatherMissionSpots(
    const MissionObservations& observations, const std::string& setup,
    bool any_setup, const std::string& laser) {
  std::map<std::string, const LocalizedImage*> pose_of;
  for (const LocalizedImage& pose : observations.poses) {
    if (pose.success) pose_of[pose.name] = &pose;
  }
  std::vector<MissionSpot> mission;
  for (const ImageSpots& image : observations.spots) {
    if (!any_setup && image.setup != setup) continue;
    const auto pose = pose_of.find(image.name);
    if (pose == pose_of.end()) continue;  // not localized
    for (const DetectedSpot& spot : image.spots) {
      if (spot.laser != laser || !spot.detected || !spot.stable) continue;
      MissionSpot m;
      m.image = image.name;
      const auto dive = observations.dives.find(image.name);
      m.dive = dive == observations.dives.end() ? 1 : dive->second;
      m.camera = pose->second->camera;
      m.cam_from_world = pose->second->cam_from_world;
      m.pixel = spot.pixel;
      m.covariance_px = spot.covariance;
      mission.push_back(m);
    }
  }
  return mission;
}

LasersFromMission CalibrateLasersFromMission(
    std::vector<LaserSetup> a_priori, const RayCaster& caster,
    const MissionObservations& observations,
    const MissionCalibrationOptions& options,
    const LasersFromMissionCallbacks& callbacks) {
  LasersFromMission result;
  result.report = {{"format", "uwmetric-lasers-from-mission"},
                   {"version", 1},
                   {"setups", nlohmann::json::array()}};
  // One set-up in --origins takes every image.
  const bool any_setup = a_priori.size() == 1;
  for (LaserSetup& setup : a_priori) {
    nlohmann::json setup_report = {{"name", setup.name},
                                   {"lasers", nlohmann::json::array()}};
    for (Laser& laser : setup.lasers) {
      const std::vector<MissionSpot> spots =
          GatherMissionSpots(observations, setup.name, any_setup, laser.name);
      if (callbacks.spots_gathered) {
        callbacks.spots_gathered(setup.name, laser.name, spots.size());
      }
      const MissionLaserCalibration calibrated =
          CalibrateLaserFromMission(laser, caster, spots, options);
      laser = calibrated.laser;
      if (callbacks.laser_calibrated) {
        callbacks.laser_calibrated(setup.name, calibrated, spots.size());
      }
      setup_report["lasers"].push_back(LaserReport(laser, spots, calibrated));
    }
    setup.Check();
    result.report["setups"].push_back(setup_report);
  }
  result.setups = std::move(a_priori);
  return result;
}

void LasersFromMissionOptions::Check() const { calibration.Check(); }

LasersFromMission CalibrateLasersFromMissionFiles(
    const LasersFromMissionOptions& options,
    const LasersFromMissionCallbacks& callbacks) {
  const Reconstruction model = ReadModel(options.input_path);
  std::vector<Eigen::Vector3d> model_points;
  for (const Point3D& point : model.Points3D()) {
    model_points.push_back(point.xyz);
  }
  MissionObservations observations;
  observations.poses = ReadLaserPosesJson(options.poses_path);
  CheckPosesUseModelPoints(model_points, observations.poses, options.poses_path,
                           options.input_path);
  const RayCaster caster(ReadMesh(options.mesh_path));
  CheckMeshFitsPoses(caster, observations.poses, options.mesh_path);
  observations.spots = ReadSpotsJson(options.spots_path);
  std::vector<LaserSetup> a_priori = ReadLasersJson(options.origins_path);
  observations.dives = ReadImageDives(options.image_dives_path);
  return CalibrateLasersFromMission(std::move(a_priori), caster, observations,
                                    options.calibration, callbacks);
}

std::string DescribeMissionLaser(const std::string& setup,
                                 const MissionLaserCalibration& result,
                                 size_t num_spots) {
  const Laser& laser = result.laser;
  std::string text = fmt::format(
      "set-up {} laser {}: {} of {} spots, depths {:.3g}-{:.3g} model "
      "units; direction ({:.6f}, {:.6f}, {:.6f}), sigma {:.4f} deg, {:.3f} deg "
      "from --origins'; image-line RMS {:.3f} px",
      setup, laser.name, result.num_inliers, num_spots, result.min_depth,
      result.max_depth, laser.direction_in_cam.x(), laser.direction_in_cam.y(),
      laser.direction_in_cam.z(), result.sigma_deg,
      result.angle_from_a_priori_deg, result.rms_px);
  for (const auto& dive : result.rms_by_dive) {
    text += fmt::format("; dive {}: {:.3f} px ({})", dive.dive, dive.rms_px,
                        dive.num_spots);
  }
  return text;
}

}  // namespace uw
