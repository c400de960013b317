#include "laserscale/image_scale_estimation.h"

#include <filesystem>
#include <map>
#include <optional>
#include <utility>

#include "common/util/error.h"
#include "laserscale/spot_ray.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// The mean of the image's nominal spot hits on the mesh; none: nullopt.
std::optional<Eigen::Vector3d> HitCentroid(const LaserImage& image,
                                           const RayCaster& caster) {
  Eigen::Vector3d hit_sum = Eigen::Vector3d::Zero();
  int num_hits = 0;
  for (const std::optional<Spot>& spot : image.spots) {
    if (!spot) continue;
    const SpotHit hit =
        CastSpot(caster, image.camera, image.cam_from_world, spot->pixel);
    if (hit.point_in_world) {
      hit_sum += *hit.point_in_world;
      ++num_hits;
    }
  }
  if (num_hits == 0) return std::nullopt;
  return hit_sum / num_hits;
}

// The overlay's path in the report, copied there; empty: it has none.
std::string CopyOverlay(const std::string& image_name,
                        const ImageScaleEstimationOptions& options) {
  if (options.overlays_dir.empty()) return "";
  const fs::path overlay =
      fs::path(options.overlays_dir) /
      (fs::path(image_name).stem().string() + "_spots.png");
  if (!fs::exists(overlay)) return "";
  fs::create_directories(fs::path(options.report_dir) / "overlays");
  const fs::path copy =
      fs::path(options.report_dir) / "overlays" / overlay.filename();
  fs::copy_file(overlay, copy, fs::copy_options::overwrite_existing);
  return "overlays/" + overlay.filename().string();
}

}  // namespace

void ImageScaleEstimationOptions::Check() const {
  monte_carlo.Check();
  if ((model_draws == nullptr) != (model == nullptr)) {
    throw ErrorAt("image scale estimation: model draws need their model");
  }
  if (surface_points < 1) {
    throw ErrorAt("surface_points must be >= 1, got ", surface_points);
  }
}

const LaserSetup& FindLaserSetup(const std::vector<LaserSetup>& setups,
                                 const std::string& name,
                                 const std::string& lasers_path) {
  if (!name.empty()) {
    for (const LaserSetup& setup : setups) {
      if (setup.name == name) return setup;
    }
    throw ErrorAt(lasers_path, ": no set-up named '", name, "'");
  }
  if (setups.size() != 1) {
    throw ErrorAt(lasers_path, " has ", setups.size(),
                  " set-ups; choose one with --setup");
  }
  return setups[0];
}

LaserImage LaserImageFromDetections(const LocalizedImage& pose,
                                    const ImageSpots& spots,
                                    const LaserSetup& setup) {
  LaserImage image;
  image.name = pose.name;
  image.camera = pose.camera;
  image.matches = pose.inliers;
  image.cam_from_world = pose.cam_from_world;
  image.feature_sigma_px = pose.rms_error_px;
  for (const Laser& laser : setup.lasers) {
    std::optional<Spot> found;
    for (const DetectedSpot& spot : spots.spots) {
      if (spot.laser == laser.name && spot.stable) {
        found = Spot{spot.pixel, spot.covariance};
      }
    }
    image.spots.push_back(found);
  }
  return image;
}

std::vector<ImageEstimate> EstimateLaserImages(
    const std::vector<LocalizedImage>& poses,
    const std::vector<ImageSpots>& spots, const LaserSetup& setup,
    const RayCaster& caster, const ImageScaleEstimationOptions& options,
    const ImageEstimateCallback& done) {
  options.Check();
  std::map<std::string, const ImageSpots*> spots_by_image;
  for (const ImageSpots& image_spots : spots) {
    spots_by_image[image_spots.name] = &image_spots;
  }
  std::vector<ImageEstimate> estimates;
  for (size_t i = 0; i < poses.size(); ++i) {
    const LocalizedImage& pose = poses[i];
    ImageEstimate estimate;
    estimate.name = pose.name;
    const auto found = spots_by_image.find(pose.name);
    if (!pose.success) {
      estimate.problem = "not localized: " + pose.problem;
    } else if (found == spots_by_image.end()) {
      estimate.problem = "no entry in " + options.spots_path;
    } else {
      LaserImage image = LaserImageFromDetections(pose, *found->second, setup);
      estimate.hit_centroid = HitCentroid(image, caster);
      if (options.model_draws != nullptr && estimate.hit_centroid) {
        image.model =
            DrawsForImage(*options.model_draws, *options.model, pose,
                          *estimate.hit_centroid, options.surface_points);
      }
      const MonteCarloOptions& monte_carlo = options.monte_carlo;
      estimate.result = EstimateImageScale(image, static_cast<int>(i), setup,
                                           caster, options.method, monte_carlo);
      if (options.variance_shares) {
        for (const ScaleSource source : kScaleSources) {
          if (!monte_carlo.Samples(source) ||
              (source == ScaleSource::kModel && image.model.NumDraws() == 0)) {
            continue;
          }
          estimate.result->per_source.emplace_back(
              source,
              EstimateImageScale(image, static_cast<int>(i), setup, caster,
                                 options.method, monte_carlo.Only(source))
                  .per_iteration);
        }
      }
      estimate.overlay = CopyOverlay(pose.name, options);
    }
    if (done) done(i, poses.size(), estimate);
    estimates.push_back(std::move(estimate));
  }
  return estimates;
}

}  // namespace uw
