#include "sim/exe/observe_command.h"

#include <iostream>

#include "colmap_plugins/align/sim3.h"

namespace uw::sim {
namespace {

void AddObserveFlags(CommandLine* cli, ObserveCommandOptions* options) {
  ObserveOptions& observe = options->observe;
  cli->Add("--sim", &options->sim, "Output folder of uwsim generate")
      ->required();
  cli->Add("--output_path", &options->output_path,
           "Model folder to write (new or empty)")
      ->required();
  cli->Add("--pixel_sigma", &observe.pixel_sigma,
           "Standard deviation of the pixel noise per coordinate");
  cli->Add("--num_points", &observe.num_points,
           "3D points, each seen by at least 2 images");
  cli->Add("--seed", &observe.seed, "Random seed");
  cli->Add<ObserveInit>(
      "--init", &observe.init,
      "Poses and points: truth, or perturbed (the truth moved by a random "
      "similarity, scale 0.3-3, with pose noise)",
      ObserveInitFromName, ObserveInitName);
  cli->Add("--perturb_rotation_deg", &observe.perturb_rotation_deg,
           "perturbed: rotation noise per camera and axis");
  cli->Add("--perturb_position_m", &observe.perturb_position_m,
           "perturbed: camera centre noise per axis, world metres");
  cli->Add("--min_registration_points", &observe.min_registration_points,
           "Drop, as a mapper would not register it, every image with fewer "
           "points seen by 3 or more images (colmap's "
           "Mapper.abs_pose_min_num_inliers is 30); 0 keeps every image");
}

void RunObserve(const ObserveCommandOptions& options) {
  const ObserveSummary summary =
      ObserveSimulation(options.sim, options.output_path, options.observe);
  std::cout << "[uwsim] observe: " << summary.num_points << " points ("
            << summary.num_candidates << " sampled), "
            << summary.num_observations << " observations, init "
            << ObserveInitName(options.observe.init) << " (model_from_world "
            << ToJson(summary.model_from_world).dump() << ") written to "
            << options.output_path << std::endl;
  if (!summary.dropped_images.empty()) {
    std::cout << "[uwsim] observe: " << summary.dropped_images.size()
              << " images dropped, fewer than "
              << options.observe.min_registration_points
              << " points seen by 3 or more images:";
    for (const std::string& name : summary.dropped_images) {
      std::cout << " " << name;
    }
    std::cout << std::endl;
  }
}

}  // namespace

Subcommand ObserveCommand() {
  return MakeSubcommand<ObserveCommandOptions>(
      "observe",
      "feature tracks a perfect matcher would give (COLMAP text model)",
      "Write the feature tracks a perfect matcher and mapper would give for "
      "an uwsim output folder: points sampled on truth/mesh.ply, observed by "
      "every image that sees them, with Gaussian pixel noise; a COLMAP text "
      "model with truth/'s camera and image ids (docs/uwsim.md).\n\n"
      "Example:\n  uwsim observe --sim sim --output_path tracks "
      "--pixel_sigma 0.5 --init perturbed --min_registration_points 30",
      AddObserveFlags, RunObserve);
}

}  // namespace uw::sim
