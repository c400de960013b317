#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "calib/exe/commands.h"
#include "calib/laser_mission_calibration.h"
#include "calib/same_model_check.h"
#include "colmap_plugins/scene/model_io.h"
#include "common/cli/command.h"
#include "common/mesh/mesh.h"
#include "common/util/csv.h"
#include "common/util/error.h"
#include "common/util/file.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spots_io.h"

namespace uw {
namespace {

// image_name,dive (docs/uwcalib.md): the dive of each image, for the RMS
// per dive. Images it does not name are dive 1.
std::map<std::string, int> ReadImageDives(const std::string& path) {
  std::map<std::string, int> dives;
  if (path.empty()) return dives;
  const CsvTable table =
      CsvTable::Read(path, {"image_name", "dive"}, {"image_name", "dive"});
  for (size_t row = 0; row < table.NumRows(); ++row) {
    if (!dives.emplace(table.Text(row, "image_name"), table.Int(row, "dive", 1))
             .second) {
      throw ErrorAt(table.Where(row), ": image ", table.Text(row, "image_name"),
                    " is listed twice");
    }
  }
  return dives;
}

}  // namespace

int RunLasersFromMission(int argc, char** argv) {
  CLI::App app(
      "Laser directions from mission data (thesis ch. 6 §6.6): the origins "
      "are known (--origins, a lasers.json whose directions are only a "
      "starting point), the laser images are localized against ONE model "
      "(laserscale localize) and their spots detected (laserscale detect). "
      "Each spot is ray cast onto the model's mesh, a line is fitted per "
      "laser in the camera frame, and a Monte Carlo over the spots' "
      "covariances gives the direction's covariance. Directions carry no "
      "scale, so any model of constant scale serves; poses or a mesh of "
      "another model are refused. Prints the image-line RMS per dive "
      "(docs/uwcalib.md).\n\n"
      "Example:\n"
      "  uwcalib lasers-from-mission --input_path sparse/0 --mesh mesh.ply "
      "--spots spots.json --poses poses.json --origins origins.json --out "
      "lasers.json",
      "uwcalib lasers-from-mission");
  std::string input_path;
  std::string mesh_path;
  std::string spots_path;
  std::string poses_path;
  std::string origins_path;
  std::string out;
  std::string image_dives_path;
  std::string report_path;
  MissionCalibrationOptions options;
  app.add_option("--input_path", input_path,
                 "COLMAP model the images were localized against")
      ->required();
  app.add_option("--mesh", mesh_path, "that model's surface (PLY or OBJ)")
      ->required();
  app.add_option("--spots", spots_path, "spots.json (laserscale detect)")
      ->required();
  app.add_option("--poses", poses_path, "poses.json (laserscale localize)")
      ->required();
  app.add_option("--origins", origins_path,
                 "lasers.json with the known origins (metres, camera frame)")
      ->required();
  app.add_option("--out", out, "lasers.json to write")->required();
  app.add_option("--image_dives", image_dives_path,
                 "CSV image_name,dive for the RMS per dive (default: dive 1)");
  app.add_option("--report_path", report_path,
                 "JSON with every spot's point, inlier flag and problem");
  app.add_option("--mc", options.num_iterations, "Monte Carlo iterations")
      ->capture_default_str();
  app.add_option("--seed", options.seed, "Monte Carlo and RANSAC seed")
      ->capture_default_str();
  app.add_option("--inlier_px", options.inlier_px,
                 "a spot further from the line (seen from its camera) is an "
                 "outlier")
      ->capture_default_str();
  app.add_option("--min_spots", options.min_spots, "inlier spots per laser")
      ->capture_default_str();
  app.add_option("--min_depth_ratio", options.min_depth_ratio,
                 "farthest / nearest inlier spot depth, at least")
      ->capture_default_str();
  app.add_option("--num_threads", options.num_threads, "threads (<= 0: all)")
      ->capture_default_str();
  return RunCommand(app, argc, argv, [&] {
    options.Check();
    const Reconstruction model = ReadModel(input_path);
    std::vector<Eigen::Vector3d> model_points;
    for (const Point3D& point : model.Points3D()) {
      model_points.push_back(point.xyz);
    }
    const std::vector<LocalizedImage> poses = ReadLaserPosesJson(poses_path);
    CheckPosesUseModelPoints(model_points, poses, poses_path, input_path);
    const RayCaster caster(ReadMesh(mesh_path));
    CheckMeshFitsPoses(caster, poses, mesh_path);
    const std::vector<ImageSpots> spots = ReadSpotsJson(spots_path);
    std::vector<LaserSetup> setups = ReadLasersJson(origins_path);
    const std::map<std::string, int> dives = ReadImageDives(image_dives_path);
    std::map<std::string, const LocalizedImage*> pose_of;
    for (const LocalizedImage& pose : poses) {
      if (pose.success) pose_of[pose.name] = &pose;
    }

    nlohmann::json report = {{"format", "uwmetric-lasers-from-mission"},
                             {"version", 1},
                             {"setups", nlohmann::json::array()}};
    for (LaserSetup& setup : setups) {
      nlohmann::json setup_report = {{"name", setup.name},
                                     {"lasers", nlohmann::json::array()}};
      for (Laser& laser : setup.lasers) {
        std::vector<MissionSpot> mission;
        for (const ImageSpots& image : spots) {
          // One set-up in --origins takes every image.
          if (setups.size() > 1 && image.setup != setup.name) continue;
          const auto pose = pose_of.find(image.name);
          if (pose == pose_of.end()) continue;  // not localized
          for (const DetectedSpot& spot : image.spots) {
            if (spot.laser != laser.name || !spot.detected || !spot.stable) {
              continue;
            }
            MissionSpot m;
            m.image = image.name;
            const auto dive = dives.find(image.name);
            m.dive = dive == dives.end() ? 1 : dive->second;
            m.camera = pose->second->camera;
            m.cam_from_world = pose->second->cam_from_world;
            m.pixel = spot.pixel;
            m.covariance_px = spot.covariance;
            mission.push_back(m);
          }
        }
        std::fprintf(stderr,
                     "[lasers-from-mission] set-up %s, laser %s: %zu "
                     "stable spots in localized images\n",
                     setup.name.c_str(), laser.name.c_str(), mission.size());
        const MissionLaserCalibration result =
            CalibrateLaserFromMission(laser, caster, mission, options);
        laser = result.laser;
        std::printf(
            "set-up %s laser %s: %d of %zu spots, depths %.3g-%.3g model "
            "units; direction (%.6f, %.6f, %.6f), sigma %.4f deg, %.3f deg "
            "from --origins'; image-line RMS %.3f px",
            setup.name.c_str(), laser.name.c_str(), result.num_inliers,
            mission.size(), result.min_depth, result.max_depth,
            laser.direction_in_cam.x(), laser.direction_in_cam.y(),
            laser.direction_in_cam.z(), result.sigma_deg,
            result.angle_from_a_priori_deg, result.rms_px);
        nlohmann::json by_dive = nlohmann::json::array();
        for (const auto& dive : result.rms_by_dive) {
          std::printf("; dive %d: %.3f px (%d)", dive.dive, dive.rms_px,
                      dive.num_spots);
          by_dive.push_back({{"dive", dive.dive},
                             {"num_spots", dive.num_spots},
                             {"rms_px", dive.rms_px}});
        }
        std::printf("\n");
        nlohmann::json spot_reports = nlohmann::json::array();
        for (size_t k = 0; k < mission.size(); ++k) {
          const Eigen::Vector3d& p = result.points_in_cam[k];
          spot_reports.push_back(
              {{"image", mission[k].image},
               {"dive", mission[k].dive},
               {"point_in_cam", {p.x(), p.y(), p.z()}},
               {"inlier", static_cast<bool>(result.inliers[k])},
               {"problem", result.problems[k]}});
        }
        setup_report["lasers"].push_back(
            {{"laser", LaserJson(laser)},
             {"num_spots", mission.size()},
             {"num_inliers", result.num_inliers},
             {"depth_range_model_units", {result.min_depth, result.max_depth}},
             {"sigma_deg", result.sigma_deg},
             {"angle_from_a_priori_deg", result.angle_from_a_priori_deg},
             {"monte_carlo_iterations", result.num_iterations_used},
             {"image_line_rms_px", result.rms_px},
             {"image_line_rms_by_dive", by_dive},
             {"spots", spot_reports}});
      }
      setup.Check();
      report["setups"].push_back(setup_report);
    }
    std::vector<PendingFile> files = {
        {out, [&](std::ostream& stream) { stream << LasersJsonText(setups); }}};
    if (!report_path.empty()) {
      files.push_back({report_path, [&](std::ostream& stream) {
                         stream << report.dump(1) << "\n";
                       }});
    }
    WriteFilesAtomically(files, false);
    std::printf("[lasers-from-mission] %s\n", out.c_str());
  });
}

}  // namespace uw
