// The model's own error in the laser scale's Monte Carlo (ch4 spec §4,
// issue 16; docs/laserscale.md, "What is sampled"): the joint draws of the
// bundle adjustment's posterior that `uwcolmap covariance_estimator
// --Covariance.samples N` writes (samples.bin, deformation only), cut down
// to what one laser image's scale rests on: its camera's refined
// intrinsics, the 3D points of its localization, and the surface where its
// rays land. The scale of an image moves with all three; the Monte Carlo
// that samples only features, spots and the calibration treats the model
// as exact and gives intervals that miss the truth (the vent, seed 11).
#pragma once

#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "colmap_plugins/ba/covariance_samples.h"
#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_poses_io.h"
#include "laserscale/scale_monte_carlo.h"

namespace uw {

// A covariance folder's draws and what their scale means.
struct ModelDraws {
  CovarianceSamples samples;
  // The covariance's gauge: "priors" (the navigation fixes the datum, so
  // the draws' log scale is the navigation's own scale error), "held" or
  // "free_network" (no measurement fixes the scale).
  std::string gauge;
  double log_scale_sigma = 0.0;  // of the draws, n - 1

  bool ScaleIsNavigations() const { return gauge == "priors"; }
};

// Reads DIR/samples.bin and DIR/covariance.bin of `model`; throws
// uw::Error naming the file when either is missing, holds no draws, or
// belongs to another model or to this one adjusted since.
ModelDraws ReadModelDraws(const std::filesystem::path& dir,
                          const Reconstruction& model);

// The draws of one localized laser image (LaserImage::model). The surface
// shift of a draw is the mean delta of the `num_surface_points` model
// points nearest `surface_at` (the image's nominal laser hits): the mesh
// is made from the nominal model, and where the model's points move the
// surface moves with them. Throws uw::Error naming the image when its
// inliers have no point ids (a version 1 poses.json), an inlier's point or
// its position is not the model's, or its camera's parameters differ from
// the model's: poses localized against another model.
ImageModelDraws DrawsForImage(const ModelDraws& draws,
                              const Reconstruction& model,
                              const LocalizedImage& pose,
                              const Eigen::Vector3d& surface_at,
                              int num_surface_points);

}  // namespace uw
