#include "calib/exe/lasers_from_mission_command.h"

#include <cstdio>

#include <fmt/format.h>

#include "common/util/file.h"
#include "laserscale/laser_setup.h"

namespace uw {
namespace {

void AddLasersFromMissionFlags(CommandLine* cli,
                               LasersFromMissionCommandOptions* options) {
  LasersFromMissionOptions& mission = options->mission;
  cli->Add("--input_path", &mission.input_path,
           "COLMAP model the images were localized against")
      ->required();
  cli->Add("--mesh", &mission.mesh_path, "that model's surface (PLY or OBJ)")
      ->required();
  cli->Add("--spots", &mission.spots_path, "spots.json (laserscale detect)")
      ->required();
  cli->Add("--poses", &mission.poses_path, "poses.json (laserscale localize)")
      ->required();
  cli->Add("--origins", &mission.origins_path,
           "lasers.json with the known origins (metres, camera frame)")
      ->required();
  cli->Add("--out", &options->out, "lasers.json to write")->required();
  cli->Add("--image_dives", &mission.image_dives_path,
           "CSV image_name,dive for the RMS per dive (default: dive 1)");
  cli->Add("--report_path", &options->report_path,
           "JSON with every spot's point, inlier flag and problem");
  MissionCalibrationOptions& calibration = mission.calibration;
  cli->Add("--mc", &calibration.num_iterations, "Monte Carlo iterations");
  cli->Add("--seed", &calibration.seed, "Monte Carlo and RANSAC seed");
  cli->Add("--inlier_px", &calibration.inlier_px,
           "a spot further from the line (seen from its camera) is an "
           "outlier");
  cli->Add("--min_spots", &calibration.min_spots, "inlier spots per laser");
  cli->Add("--min_depth_ratio", &calibration.min_depth_ratio,
           "farthest / nearest inlier spot depth, at least");
  cli->Add("--num_threads", &calibration.num_threads, "threads (<= 0: all)");
}

void RunLasersFromMission(const LasersFromMissionCommandOptions& options) {
  LasersFromMissionCallbacks callbacks;
  callbacks.spots_gathered = [](const std::string& setup,
                                const std::string& laser, size_t num_spots) {
    fmt::print(stderr,
               "[lasers-from-mission] set-up {}, laser {}: {} "
               "stable spots in localized images\n",
               setup.c_str(), laser.c_str(), num_spots);
  };
  callbacks.laser_calibrated = [](const std::string& setup,
                                  const MissionLaserCalibration& result,
                                  size_t num_spots) {
    fmt::print("{}\n", DescribeMissionLaser(setup, result, num_spots).c_str());
  };
  const LasersFromMission result =
      CalibrateLasersFromMissionFiles(options.mission, callbacks);
  std::vector<PendingFile> files = {{options.out, [&](std::ostream& stream) {
                                       stream << LasersJsonText(result.setups);
                                     }}};
  if (!options.report_path.empty()) {
    files.push_back({options.report_path, [&](std::ostream& stream) {
                       stream << result.report.dump(1) << "\n";
                     }});
  }
  WriteFilesAtomically(files, false);
  fmt::print("[lasers-from-mission] {}\n", options.out.c_str());
}

}  // namespace

Subcommand LasersFromMissionCommand() {
  return MakeSubcommand<LasersFromMissionCommandOptions>(
      "lasers-from-mission",
      "laser directions from spots in localized mission images",
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
      AddLasersFromMissionFlags, RunLasersFromMission);
}

}  // namespace uw
