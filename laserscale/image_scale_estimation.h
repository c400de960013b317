// `laserscale estimate`'s per-image step: each localized laser image
// (poses.json) with its detected spots (spots.json) becomes the LaserImage
// that EstimateImageScale takes, and its ImageEstimate for CombineImages.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/mesh/ray_caster.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/laser_setup.h"
#include "laserscale/model_draws.h"
#include "laserscale/scale_report.h"
#include "laserscale/spots_io.h"

namespace uw {

// The set-up named `name` of lasers.json (read from `lasers_path`), or its
// only one when `name` is empty; throws uw::Error otherwise.
const LaserSetup& FindLaserSetup(const std::vector<LaserSetup>& setups,
                                 const std::string& name,
                                 const std::string& lasers_path);

// The image to estimate from: the localization's camera, pose, inliers and
// RMS error (the feature noise), and per laser of `setup`, in its order,
// the laser's last stable spot of `spots` (none: std::nullopt).
LaserImage LaserImageFromDetections(const LocalizedImage& pose,
                                    const ImageSpots& spots,
                                    const LaserSetup& setup);

struct ImageScaleEstimationOptions {
  ScaleMethod method = ScaleMethod::kFum;
  MonteCarloOptions monte_carlo;
  // spots.json, named in the problem of an image it has no entry for.
  std::string spots_path;
  // detect's overlays (NAME_spots.png); empty: none. Each one found is
  // copied into report_dir/overlays for the report to link.
  std::string overlays_dir;
  std::string report_dir;
  // Each sampled source also alone, for its share of the variance (one
  // more Monte Carlo per source and image).
  bool variance_shares = true;
  // The model's draws and the model they belong to (both or neither);
  // none: the model is taken as exact.
  const ModelDraws* model_draws = nullptr;
  const Reconstruction* model = nullptr;
  // Model points whose mean delta moves the surface under an image's hits.
  int surface_points = 8;

  void Check() const;
};

// Called after each image with its index, the number of images and its
// estimate.
using ImageEstimateCallback = std::function<void(
    size_t index, size_t count, const ImageEstimate& estimate)>;

// One estimate per pose, in order; an image that is not localized or has
// no spots gets its problem instead of a result. Image i's Monte Carlo is
// the i-th of the seed's streams (EstimateImageScale); with model draws,
// each image's are cut from them (DrawsForImage) at its nominal hits.
std::vector<ImageEstimate> EstimateLaserImages(
    const std::vector<LocalizedImage>& poses,
    const std::vector<ImageSpots>& spots, const LaserSetup& setup,
    const RayCaster& caster, const ImageScaleEstimationOptions& options,
    const ImageEstimateCallback& done = nullptr);

}  // namespace uw
