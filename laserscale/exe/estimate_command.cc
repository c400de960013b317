#include <cstdio>
#include <filesystem>
#include <map>

#include "common/cli/command.h"
#include "common/mesh/mesh.h"
#include "common/mesh/ray_caster.h"
#include "common/util/error.h"
#include "laserscale/exe/commands.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/laser_setup.h"
#include "laserscale/scale_report.h"
#include "laserscale/spot_ray.h"
#include "laserscale/spots_io.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

const LaserSetup& ChooseSetup(const std::vector<LaserSetup>& setups,
                              const std::string& wanted,
                              const std::string& lasers_path) {
  if (!wanted.empty()) {
    for (const LaserSetup& setup : setups) {
      if (setup.name == wanted) return setup;
    }
    throw ErrorAt(lasers_path, ": no set-up named '", wanted, "'");
  }
  if (setups.size() != 1) {
    throw ErrorAt(lasers_path, " has ", setups.size(),
                  " set-ups; choose one with --setup");
  }
  return setups[0];
}

}  // namespace

int RunEstimate(int argc, char** argv) {
  CLI::App app(
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
      "laserscale estimate");
  std::string mesh_path;
  std::string poses_path;
  std::string spots_path;
  std::string lasers_path;
  std::string setup_name;
  std::string method_name = "fum";
  std::string overlays_dir;
  std::string out;
  MonteCarloOptions options;
  CombineOptions combine;
  app.add_option("--mesh", mesh_path,
                 "The model's surface, model units and frame (.ply, .obj)")
      ->required();
  app.add_option("--poses", poses_path, "poses.json of laserscale localize")
      ->required();
  app.add_option("--spots", spots_path, "spots.json of laserscale detect")
      ->required();
  app.add_option("--lasers", lasers_path, "lasers.json (the calibration)")
      ->required();
  app.add_option("--setup", setup_name,
                 "Set-up of lasers.json (default: the only one)");
  app.add_option("--method", method_name, "fum, pcm, direct or davis_tusting")
      ->capture_default_str();
  app.add_option("--mc", options.num_iterations,
                 "Monte Carlo iterations per image")
      ->capture_default_str();
  app.add_option("--seed", options.seed, "Seed of the Monte Carlo")
      ->capture_default_str();
  app.add_option("--num_threads", options.num_threads,
                 "Threads (<= 0: all); the result does not depend on it")
      ->capture_default_str();
  app.add_option("--min_lasers", options.min_lasers,
                 "An image needs this many confident spots")
      ->capture_default_str();
  app.add_option("--max_item_sigmas", options.max_item_sigmas,
                 "Reject an image with a laser (pair) whose scale lies "
                 "further from the median than this many of its sigmas")
      ->capture_default_str();
  app.add_option("--segment_radius", combine.segment_radius,
                 "Segment radius in model units")
      ->capture_default_str();
  app.add_option("--overlays", overlays_dir,
                 "Folder of detect's spot overlays, to link from the report");
  app.add_option("--out", out, "Report folder")->required();
  return RunCommand(app, argc, argv, [&] {
    options.Check();
    combine.Check();
    const ScaleMethod method = ScaleMethodFromName(method_name);
    const std::vector<LaserSetup> setups = ReadLasersJson(lasers_path);
    const LaserSetup& setup = ChooseSetup(setups, setup_name, lasers_path);
    const std::vector<LocalizedImage> poses = ReadLaserPosesJson(poses_path);
    std::map<std::string, ImageSpots> spots_by_image;
    for (ImageSpots& spots : ReadSpotsJson(spots_path)) {
      spots_by_image[spots.name] = std::move(spots);
    }
    std::printf("[estimate] reading the mesh %s\n", mesh_path.c_str());
    std::fflush(stdout);
    const RayCaster caster(ReadMesh(mesh_path));
    std::vector<ImageEstimate> estimates;
    for (size_t i = 0; i < poses.size(); ++i) {
      const LocalizedImage& pose = poses[i];
      ImageEstimate estimate;
      estimate.name = pose.name;
      const auto spots = spots_by_image.find(pose.name);
      if (!pose.success) {
        estimate.problem = "not localized: " + pose.problem;
      } else if (spots == spots_by_image.end()) {
        estimate.problem = "no entry in " + spots_path;
      } else {
        LaserImage image;
        image.name = pose.name;
        image.camera = pose.camera;
        image.matches = pose.inliers;
        image.cam_from_world = pose.cam_from_world;
        image.feature_sigma_px = pose.rms_error_px;
        Eigen::Vector3d hit_sum = Eigen::Vector3d::Zero();
        int num_hits = 0;
        for (const Laser& laser : setup.lasers) {
          std::optional<Spot> found;
          for (const DetectedSpot& spot : spots->second.spots) {
            if (spot.laser == laser.name && spot.stable) {
              found = Spot{spot.pixel, spot.covariance};
            }
          }
          if (found) {
            const SpotHit hit = CastSpot(caster, image.camera,
                                         image.cam_from_world, found->pixel);
            if (hit.point_in_world) {
              hit_sum += *hit.point_in_world;
              ++num_hits;
            }
          }
          image.spots.push_back(found);
        }
        if (num_hits > 0) estimate.hit_centroid = hit_sum / num_hits;
        estimate.result = EstimateImageScale(image, static_cast<int>(i), setup,
                                             caster, method, options);
        if (!overlays_dir.empty()) {
          const fs::path overlay =
              fs::path(overlays_dir) /
              (fs::path(pose.name).stem().string() + "_spots.png");
          if (fs::exists(overlay)) {
            fs::create_directories(fs::path(out) / "overlays");
            const fs::path copy =
                fs::path(out) / "overlays" / overlay.filename();
            fs::copy_file(overlay, copy, fs::copy_options::overwrite_existing);
            estimate.overlay = "overlays/" + overlay.filename().string();
          }
        }
      }
      if (estimate.result) {
        const ImageScaleResult& r = *estimate.result;
        std::printf("[estimate %zu/%zu] %s: %s %.5f +- %.5f%s%s\n", i + 1,
                    poses.size(), pose.name.c_str(),
                    ScaleMethodName(method).c_str(),
                    r.nominal ? *r.nominal : 0.0, r.monte_carlo.std_dev,
                    r.accepted ? "" : ", rejected: ", r.rejection.c_str());
      } else {
        std::printf("[estimate %zu/%zu] %s: skipped: %s\n", i + 1, poses.size(),
                    pose.name.c_str(), estimate.problem.c_str());
      }
      std::fflush(stdout);
      estimates.push_back(std::move(estimate));
    }
    const ModelScaleReport report =
        CombineImages(std::move(estimates), method, options, combine);
    WriteScaleReport(report, out);
    const CombinedScale& model = report.model;
    if (!model.nominal) {
      throw ErrorAt("no laser image was accepted, so there is no scale; see ",
                    (fs::path(out) / "index.html").string());
    }
    std::printf(
        "[estimate] scale s = %.5f, 95 %% interval [%.5f, %.5f] (sigma "
        "%.5f, %zu of %zu images, Birge ratio %.2f); report %s\n",
        *model.nominal, model.ci95_low, model.ci95_high, model.sigma,
        model.images.size(), report.images.size(), model.birge_ratio,
        (fs::path(out) / "index.html").c_str());
  });
}

}  // namespace uw
