// What `colmap model_analyzer` reports about a model, computed from the
// files, plus reprojection errors recomputed with our camera models (which
// checks the stored per-point errors against the poses, cameras and points).
#pragma once

#include <string>

#include "colmap_plugins/scene/model.h"

namespace uw {

struct ModelStats {
  size_t num_cameras = 0;
  size_t num_images = 0;
  size_t num_reg_images = 0;
  size_t num_points3D = 0;
  // 2D points that observe a 3D point, over all registered images.
  size_t num_observations = 0;
  double mean_track_length = 0.0;
  double mean_observations_per_image = 0.0;
  // Mean of the points' stored errors (those not -1), as COLMAP computes it.
  double mean_reprojection_error = 0.0;
};

ModelStats ComputeModelStats(const Reconstruction& reconstruction);

// The lines `colmap model_analyzer` (3.8) prints, in its format.
std::string FormatModelAnalyzerReport(const ModelStats& stats);

struct ReprojectionErrors {
  // Per point: mean Euclidean pixel error over its track, as COLMAP defines
  // a point's error; then the mean over points.
  double mean_point_error = 0.0;
  // Mean over all observations.
  double mean_observation_error = 0.0;
  // Largest |recomputed − stored| over points with a stored error.
  double max_stored_error_difference = 0.0;
  // Observations whose point lies behind the camera (COLMAP would count
  // them as infinitely wrong); they are left out of the means.
  size_t num_behind_camera = 0;
  size_t num_observations = 0;
};

ReprojectionErrors RecomputeReprojectionErrors(
    const Reconstruction& reconstruction);

}  // namespace uw
