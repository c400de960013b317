#include "laserscale/exe/estimate_command.h"

#include <filesystem>

#include <fmt/format.h>

#include "common/mesh/mesh.h"
#include "common/util/error.h"
#include "laserscale/exe/scale_method_flags.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

void AddEstimateFlags(CommandLine* cli, EstimateOptions* options) {
  ImageScaleEstimationOptions& images = options->images;
  MonteCarloOptions& monte_carlo = images.monte_carlo;
  cli->Add("--mesh", &options->mesh_path,
           "The model's surface, model units and frame (.ply, .obj)")
      ->required();
  cli->Add("--poses", &options->poses_path, "poses.json of laserscale localize")
      ->required();
  cli->Add("--spots", &images.spots_path, "spots.json of laserscale detect")
      ->required();
  cli->Add("--lasers", &options->lasers_path, "lasers.json (the calibration)")
      ->required();
  cli->Add("--setup", &options->setup_name,
           "Set-up of lasers.json (default: the only one)");
  AddScaleMethodFlag(cli, "--method", &images.method,
                     "fum, pcm, direct or davis_tusting");
  cli->Add("--mc", &monte_carlo.num_iterations,
           "Monte Carlo iterations per image");
  cli->Add("--seed", &monte_carlo.seed, "Seed of the Monte Carlo");
  cli->Add("--num_threads", &monte_carlo.num_threads,
           "Threads (<= 0: all); the result does not depend on it");
  cli->Add("--min_lasers", &monte_carlo.min_lasers,
           "An image needs this many confident spots");
  cli->Add("--max_item_sigmas", &monte_carlo.max_item_sigmas,
           "Reject an image with a laser (pair) whose scale lies "
           "further from the median than this many of its sigmas");
  cli->Add("--segment_radius", &options->combine.segment_radius,
           "Segment radius in model units");
  cli->Add("--overlays", &images.overlays_dir,
           "Folder of detect's spot overlays, to link from the report");
  cli->Add("--out", &images.report_dir, "Report folder")->required();
}

void RunEstimate(const EstimateOptions& options) {
  const ImageScaleEstimationOptions& images = options.images;
  const std::vector<LaserSetup> setups = ReadLasersJson(options.lasers_path);
  const LaserSetup& setup =
      FindLaserSetup(setups, options.setup_name, options.lasers_path);
  const std::vector<LocalizedImage> poses =
      ReadLaserPosesJson(options.poses_path);
  const std::vector<ImageSpots> spots = ReadSpotsJson(images.spots_path);
  fmt::print("[estimate] reading the mesh {}\n", options.mesh_path.c_str());
  std::fflush(stdout);
  const RayCaster caster(ReadMesh(options.mesh_path));
  const std::string method = ScaleMethodName(images.method);
  std::vector<ImageEstimate> estimates = EstimateLaserImages(
      poses, spots, setup, caster, images,
      [&](size_t i, size_t count, const ImageEstimate& estimate) {
        if (estimate.result) {
          const ImageScaleResult& r = *estimate.result;
          fmt::print("[estimate {}/{}] {}: {} {:.5f} +- {:.5f}{}{}\n", i + 1,
                     count, estimate.name.c_str(), method.c_str(),
                     r.nominal ? *r.nominal : 0.0, r.monte_carlo.std_dev,
                     r.accepted ? "" : ", rejected: ", r.rejection.c_str());
        } else {
          fmt::print("[estimate {}/{}] {}: skipped: {}\n", i + 1, count,
                     estimate.name.c_str(), estimate.problem.c_str());
        }
        std::fflush(stdout);
      });
  const ModelScaleReport report = CombineImages(
      std::move(estimates), images.method, images.monte_carlo, options.combine);
  WriteScaleReport(report, images.report_dir);
  const CombinedScale& model = report.model;
  const std::string index =
      (fs::path(images.report_dir) / "index.html").string();
  if (!model.nominal) {
    throw ErrorAt("no laser image was accepted, so there is no scale; see ",
                  index);
  }
  fmt::print(
      "[estimate] scale s = {:.5f}, 95 % interval [{:.5f}, {:.5f}] (sigma "
      "{:.5f}, {} of {} images, Birge ratio {:.2f}); report {}\n",
      *model.nominal, model.ci95_low, model.ci95_high, model.sigma,
      model.images.size(), report.images.size(), model.birge_ratio,
      index.c_str());
}

}  // namespace

Subcommand EstimateCommand() {
  return MakeSubcommand<EstimateOptions>(
      "estimate",
      "the model's scale with its confidence interval (Monte Carlo)",
      "The scale of a COLMAP model from its localized laser images: each "
      "confident spot is cast onto the model's mesh through the image's "
      "camera, the method (FUM by default) compares the laser geometry known "
      "in metres with the same quantity measured through the model, and a "
      "Monte Carlo per image re-samples features, spots and the calibration "
      "to give the uncertainty. Images are combined into the model's scale "
      "with a 95 % interval, and into segments. Multiply the model by the "
      "scale s to get metres (laserscale apply).\n\n"
      "Example:\n"
      "  laserscale estimate --mesh mesh.ply --poses poses.json --spots "
      "spots.json --lasers lasers.json --method fum --mc 5000 --out report",
      AddEstimateFlags, RunEstimate);
}

}  // namespace uw
