#include "colmap_plugins/ba/noise_levels.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <Eigen/Cholesky>

#include "colmap_plugins/ba/prior_alignment.h"
#include "common/util/error.h"

namespace uw {

NoiseLevels EstimateNoiseLevels(const NavBundleAdjustmentOptions& options,
                                const std::vector<ImagePosePrior>& priors,
                                const Reconstruction& model) {
  Reconstruction images_only = model;
  NavBundleAdjustmentOptions plain = options;
  plain.estimate_offset_covariance = false;
  const NavBundleAdjustmentReport report =
      AdjustWithNavigation(plain, {}, nullptr, {}, &images_only);

  NoiseLevels levels;
  levels.warnings = report.warnings;
  double free_intrinsics = 0.0;
  for (const Camera& camera : images_only.Cameras()) {
    free_intrinsics += static_cast<double>(camera.params.size()) -
                       ConstantCameraParams(options, camera.model_id).size();
  }
  const double unknowns =
      3.0 * report.num_points + 6.0 * report.num_images - 7.0 + free_intrinsics;
  levels.reprojection_dof = 2.0 * report.num_observations - unknowns;
  if (!(levels.reprojection_dof > 0.0)) {
    throw ErrorAt("the images leave no degrees of freedom to estimate their ",
                  "noise: ", report.num_observations, " observations for ",
                  unknowns, " unknowns");
  }
  levels.pixel_sigma =
      std::sqrt(report.final_terms.at("reprojection").mean_squared *
                report.num_observations / levels.reprojection_dof);

  // Whitened residuals of the least-squares fit of a similarity and one
  // offset per dive but the reference one: their 3N - 7 - 3(D - 1) degrees
  // of freedom are that fit's. The robust alignment (RANSAC at 4 stated
  // sigmas, Huber) is only the start: it calls the larger errors of a log
  // noisier than it states outliers and leaves them whole (on the vent plan
  // with 3x the stated noise, s_n 4.1 +- 1.0 over 8 draws where the
  // least-squares fit gives 3.0). The two are fitted in turn to convergence.
  AlignToPriors(priors, &images_only);
  std::set<int> dives;
  for (const ImagePosePrior& prior : priors) dives.insert(prior.dive);
  const int reference_dive =
      options.reference_dive != 0 ? options.reference_dive : *dives.begin();
  std::map<int, Eigen::Vector3d> offsets;
  for (const int dive : dives) offsets[dive] = Eigen::Vector3d::Zero();
  SimilarityOptions least_squares;
  least_squares.robust = false;
  constexpr int kMaxRounds = 100;
  // The largest move of a camera, against the navigation's stated sigma.
  const double converged_m = 1e-6 * NavSigma(priors);
  for (int round = 0; round < kMaxRounds; ++round) {
    for (const int dive : dives) {
      if (!options.dive_offsets || dive == reference_dive) continue;
      Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
      Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
      for (const ImagePosePrior& prior : priors) {
        if (prior.dive != dive) continue;
        const Eigen::Matrix3d w = prior.position_covariance.inverse();
        information += w;
        weighted +=
            w * (images_only.FindImage(prior.image_id)->ProjectionCenter() -
                 prior.position_in_world);
      }
      offsets[dive] = information.ldlt().solve(weighted);
    }
    std::vector<ImagePosePrior> shifted = priors;
    for (ImagePosePrior& prior : shifted) {
      prior.position_in_world += offsets.at(prior.dive);
    }
    const Sim3d step =
        AlignToPriors(shifted, &images_only, least_squares).b_from_a;
    double largest_move_m = 0.0;
    for (const Image& image : images_only.Images()) {
      const Eigen::Vector3d centre = image.ProjectionCenter();
      largest_move_m =
          std::max(largest_move_m, (centre - step.Inverse() * centre).norm());
    }
    if (largest_move_m < converged_m) break;
  }
  double chi2 = 0.0;
  for (const ImagePosePrior& prior : priors) {
    const Eigen::Vector3d error =
        images_only.FindImage(prior.image_id)->ProjectionCenter() -
        prior.position_in_world - offsets.at(prior.dive);
    chi2 += error.dot(prior.position_covariance.ldlt().solve(error));
  }
  const double num_offsets =
      options.dive_offsets ? static_cast<double>(dives.size()) - 1.0 : 0.0;
  levels.navigation_dof = 3.0 * priors.size() - 7.0 - 3.0 * num_offsets;
  if (!(levels.navigation_dof > 0.0)) {
    throw ErrorAt("the ", priors.size(),
                  " navigation priors leave no degrees of freedom to "
                  "estimate their noise");
  }
  levels.nav_scale = std::sqrt(chi2 / levels.navigation_dof);
  levels.stated_nav_sigma_m = NavSigma(priors);
  levels.nav_sigma_m = levels.nav_scale * levels.stated_nav_sigma_m;
  if (!(levels.nav_sigma_m > 0.0 && std::isfinite(levels.nav_sigma_m))) {
    throw ErrorAt("the navigation noise estimate is ", levels.nav_sigma_m,
                  " m: the priors fit the images exactly, so lambda is "
                  "undefined; give --Nav.weight explicitly");
  }
  levels.weight_px_per_m = levels.pixel_sigma / levels.nav_sigma_m;
  return levels;
}

}  // namespace uw
