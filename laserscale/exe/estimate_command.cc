#include "laserscale/exe/estimate_command.h"

#include <filesystem>

#include <fmt/format.h>

#include "colmap_plugins/align/mesh_frame.h"
#include "colmap_plugins/scene/model_io.h"
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
           "The model's surface, model units and frame (.ply, .obj; STL, glTF "
           "and other formats through Assimp)")
      ->required();
  cli->Add("--poses", &options->poses_path, "poses.json of laserscale localize")
      ->required();
  cli->Add("--spots", &images.spots_path, "spots.json of laserscale detect")
      ->required();
  cli->Add("--lasers", &options->lasers_path, "lasers.json (the calibration)")
      ->required();
  cli->Add("--setup", &options->setup_name,
           "Set-up of lasers.json (default: the only one)");
  cli->Add("--covariance", &options->covariance_path,
           "The model's covariance folder (uwcolmap covariance_estimator "
           "--Covariance.samples 200): re-sample the model's intrinsics, "
           "points and surface; without it the model is taken as exact");
  cli->Add("--input_path", &options->input_path,
           "The COLMAP model the covariance and poses.json belong to (with "
           "--covariance)");
  cli->Add("--surface_points", &images.surface_points,
           "Model points whose mean draw moves the surface under an image's "
           "laser hits");
  cli->Add("--variance_shares", &images.variance_shares,
           "Also run each source alone, for its share of the variance (1/0)");
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
  // The laser images were localized in the model: they must look at its
  // mesh, or every range below would be to another surface.
  std::vector<Rigid3d> localized;
  for (const LocalizedImage& pose : poses) {
    if (pose.success) localized.push_back(pose.cam_from_world);
  }
  RequireMeshInModelFrame(CheckMeshFrame(localized, caster, std::nullopt),
                          options.mesh_path, options.poses_path);
  const std::string method = ScaleMethodName(images.method);
  std::optional<Reconstruction> colmap_model;
  std::optional<ModelDraws> draws;
  ImageScaleEstimationOptions with_model = images;
  if (!options.covariance_path.empty()) {
    colmap_model = ReadModel(options.input_path);
    draws = ReadModelDraws(options.covariance_path, *colmap_model);
    with_model.model = &*colmap_model;
    with_model.model_draws = &*draws;
    fmt::print(
        "[estimate] {} draws of the model's covariance (gauge {}, log scale "
        "sigma {:.4f})\n",
        draws->samples.NumSamples(), draws->gauge.c_str(),
        draws->log_scale_sigma);
    if (images.monte_carlo.num_iterations % draws->samples.NumSamples() != 0) {
      fmt::print(
          "[estimate] note: {} iterations are not a multiple of the {} "
          "draws; the first ones are used once more than the others\n",
          images.monte_carlo.num_iterations, draws->samples.NumSamples());
    }
  } else {
    fmt::print(
        "[estimate] warning: no --covariance: the model is taken as exact, "
        "so the interval leaves out its own error\n");
  }
  std::fflush(stdout);
  std::vector<ImageEstimate> estimates = EstimateLaserImages(
      poses, spots, setup, caster, with_model,
      [&](size_t i, size_t count, const ImageEstimate& estimate) {
        if (estimate.result) {
          const ImageScaleResult& r = *estimate.result;
          fmt::print("[estimate {}/{}] {}: {} {:.5f} +- {:.5f}{}{}\n", i + 1,
                     count, estimate.name.c_str(), method.c_str(),
                     r.nominal ? *r.nominal : 0.0, r.monte_carlo.std_dev,
                     r.accepted ? "" : ", rejected: ", r.rejection.c_str());
          if (!r.model_note.empty()) {
            fmt::print("  model: {}\n", r.model_note.c_str());
          }
        } else {
          fmt::print("[estimate {}/{}] {}: skipped: {}\n", i + 1, count,
                     estimate.name.c_str(), estimate.problem.c_str());
        }
        std::fflush(stdout);
      });
  ModelScaleReport report = CombineImages(std::move(estimates), images.method,
                                          images.monte_carlo, options.combine);
  if (draws) {
    report.num_model_draws = draws->samples.NumSamples();
    report.model_gauge = draws->gauge;
    if (draws->ScaleIsNavigations()) {
      report.navigation =
          CheckAgainstNavigation(report.model, draws->log_scale_sigma);
    }
  }
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
  if (!model.source_sigmas.empty()) {
    std::string shares;
    for (const auto& [source, sigma] : model.source_sigmas) {
      shares += fmt::format("{}{} {:.0f} %", shares.empty() ? "" : ", ",
                            ScaleSourceName(source),
                            100.0 * model.VarianceShare(sigma));
    }
    fmt::print("[estimate] share of the variance: {}\n", shares.c_str());
  }
  if (report.navigation) {
    const NavigationScaleCheck& check = *report.navigation;
    fmt::print(
        "[estimate] {}the laser scale against the navigation's (scale sigma "
        "{:.4f}): z = {:+.2f}{}\n",
        check.consistent ? "" : "WARNING: ", check.log_scale_sigma, check.z,
        check.consistent ? "" : ", beyond 3 sigma: one of them is wrong");
  }
}

}  // namespace

void EstimateOptions::Check() const {
  images.Check();
  combine.Check();
  if (covariance_path.empty() != input_path.empty()) {
    throw Error("--covariance and --input_path go together");
  }
}

Subcommand EstimateCommand() {
  return MakeSubcommand<EstimateOptions>(
      "estimate",
      "the model's scale with its confidence interval (Monte Carlo)",
      "The scale of a COLMAP model from its localized laser images: each "
      "confident spot is cast onto the model's mesh through the image's "
      "camera, the method (FUM by default) compares the laser geometry known "
      "in metres with the same quantity measured through the model, and a "
      "Monte Carlo per image re-samples features, spots, the calibration "
      "and, with --covariance, the model's intrinsics, points and surface "
      "to give the uncertainty, and each source alone for its share. Images "
      "are combined into the model's scale "
      "with a 95 % interval, and into segments. Multiply the model by the "
      "scale s to get metres (laserscale apply).\n\n"
      "Example:\n"
      "  laserscale estimate --mesh mesh.ply --poses poses.json --spots "
      "spots.json --lasers lasers.json --method fum --mc 5000 --covariance "
      "cov --input_path sparse/0 --out report",
      AddEstimateFlags, RunEstimate);
}

}  // namespace uw
