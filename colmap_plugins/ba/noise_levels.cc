#include "colmap_plugins/ba/noise_levels.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include <Eigen/Cholesky>

#include "colmap_plugins/ba/prior_alignment.h"
#include "colmap_plugins/ba/scale_transfer.h"
#include "common/util/error.h"

namespace uw {

NoiseLevels EstimateNoiseLevels(const NavBundleAdjustmentOptions& options,
                                const std::vector<ImagePosePrior>& priors,
                                const Reconstruction& model) {
  Reconstruction images_only = model;
  NavBundleAdjustmentOptions plain = options;
  plain.estimate_offset_covariance = false;
  NavBundleAdjustmentReport report;
  try {
    report = AdjustWithNavigation(plain, {}, nullptr, {}, &images_only);
  } catch (const Error& error) {
    throw ErrorAt("the images-only adjustment behind --Nav.weight auto: ",
                  error.what());
  }

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
  // of freedom are that fit's. Least squares, not robust: a robust fit
  // calls the larger errors of a log noisier than it states outliers and
  // leaves them whole (on the vent plan with 3x the stated noise, s_n
  // 4.1 +- 1.0 over 8 draws where least squares gives 3.0). Jointly, not in
  // turn: fitted in turn, the offsets and the similarity crawl along a
  // shallow valley when the dives lie apart, and a stop short of its floor
  // leaves the dives' biases in the residuals (similarity_with_offsets.h).
  //
  // Only the images that points seen by 3 images link into one group are a
  // similarity of the truth: a group apart keeps a pose and scale of its
  // own in the images-only adjustment, which the fit would count as
  // navigation noise (a seafloor dive whose images share no such point
  // with the others: sigma_n 2-14x the realised noise).
  const std::vector<image_t> apart = ImagesWithoutScaleTransfer(images_only);
  const std::set<image_t> apart_set(apart.begin(), apart.end());
  std::vector<ImagePosePrior> linked;
  std::vector<Eigen::Vector3d> centres;
  for (const ImagePosePrior& prior : priors) {
    const Eigen::Vector3d centre = CenterOfPriorImage(images_only, prior);
    if (apart_set.count(prior.image_id) != 0) continue;
    linked.push_back(prior);
    centres.push_back(centre);
  }
  if (linked.size() < priors.size()) {
    levels.warnings.push_back(fmt::format(
        "{} of the {} priors are of images that share no point that 3 images "
        "see with the rest, whose pose and scale the images leave free: the "
        "navigation's noise is estimated from the other {}",
        priors.size() - linked.size(), priors.size(), linked.size()));
  }
  NavBundleAdjustmentOptions fit_options = options;
  if (std::none_of(linked.begin(), linked.end(), [&](const auto& prior) {
        return prior.dive == options.reference_dive;
      })) {
    fit_options.reference_dive = 0;  // the lowest dive left
  }
  SimilarityWithOffsets fit;
  try {
    fit = FitToPriors(linked, centres, fit_options);
  } catch (const Error& error) {
    throw ErrorAt(
        "the navigation's noise cannot be estimated from the ", linked.size(),
        " priors of images the images link",
        linked.size() < priors.size()
            ? fmt::format(" ({} of {} left out: their images share no point "
                          "that 3 images see with the rest)",
                          priors.size() - linked.size(), priors.size())
            : std::string(),
        ": ", error.what(), "; give --Nav.weight explicitly");
  }
  if (options.dive_offsets) levels.dive_offsets = fit.offsets;
  const double chi2 = fit.chi_square;
  const double num_offsets = options.dive_offsets
                                 ? static_cast<double>(fit.offsets.size()) - 1.0
                                 : 0.0;
  levels.navigation_dof = 3.0 * linked.size() - 7.0 - 3.0 * num_offsets;
  if (!(levels.navigation_dof > 0.0)) {
    throw ErrorAt("the ", linked.size(),
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
