#include "colmap_plugins/ba/noise_levels.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include <Eigen/Cholesky>

#include "colmap_plugins/ba/difference_noise.h"
#include "colmap_plugins/ba/prior_alignment.h"
#include "colmap_plugins/ba/scale_transfer.h"
#include "common/util/error.h"

namespace uw {

namespace {

// Departures of the similarity's residuals from the noise smaller than this
// are not worth a warning (a smooth part 0.75x the noise).
constexpr double kMinDepartureRatio = 1.25;
// Differences over 2 images exceeding those over 1 by less than this are
// not taken for shared errors, whatever the count (a gentle bend of the
// model raises those over 2 a little). A filtered log whose neighbouring
// errors correlate by rho (first order) gives sqrt(1 + rho) at most: 1.18
// at rho 0.4, 1.28 at 0.5, 1.41 at 0.9; seen at 1.2 and beyond only with
// enough differences for the 3-sigma test (about 75 at rho 0.5). uwsim's
// 15 multi-dive chains: 0.68-1.18.
constexpr double kMinSharedErrorRatio = 1.2;

// Replaces levels->nav_scale (the similarity's) by the second differences'
// (difference_noise.h) unless neighbouring images share their errors, and
// warns when the similarity's residuals exceed the differences' by more than
// 3 sigmas of the two estimates: the residuals then hold a smooth departure
// of the model, or of the navigation, that white noise does not explain.
// `by_dive`: the dives are sequences of their own (with offsets; without,
// the adjuster sees one navigation, and so do the differences).
void ChooseDifferenceScale(
    const std::vector<ImagePosePrior>& priors,
    const std::vector<Eigen::Vector3d>& residuals,
    const std::unordered_map<image_t, double>& image_times, bool by_dive,
    NoiseLevels* levels) {
  std::vector<TimedResidual> timed;
  for (size_t i = 0; i < priors.size(); ++i) {
    const auto time = image_times.find(priors[i].image_id);
    if (time == image_times.end()) return;  // no clock, no order
    timed.push_back({by_dive ? priors[i].dive : 1, time->second, residuals[i],
                     priors[i].position_covariance});
  }
  const auto lag1 = EstimateDifferenceNoise(timed, 1);
  const auto lag2 = EstimateDifferenceNoise(timed, 2);
  if (!lag1 || !lag2) return;
  levels->difference_nav_scale = lag1->scale;
  levels->difference_lag2_nav_scale = lag2->scale;
  const double shared_ratio = lag2->scale / lag1->scale;
  const double departure = levels->fit_nav_scale / lag1->scale;
  if (shared_ratio > std::max(kMinSharedErrorRatio,
                              1.0 + 3.0 * std::hypot(lag1->RelativeSigma(),
                                                     lag2->RelativeSigma()))) {
    if (departure > kMinDepartureRatio) {
      levels->warnings.push_back(fmt::format(
          "the navigation's residuals to the images-only model differ more "
          "over 2 images than over 1 ({:.3g}x): neighbouring images share "
          "their navigation errors (a log interpolated between fixes, or "
          "filtered), or the images-only model departs from the truth "
          "within a few images. The navigation's noise is taken from the "
          "whole residual, {:.3g}x the image-to-image one: too large if the "
          "model departs (lambda too small); if the images share errors, "
          "the adjustment, which takes them as independent, understates "
          "the uncertainty of the model's placement",
          shared_ratio, departure));
    }
    return;
  }
  levels->nav_scale = lag1->scale;
  const double fit_relative_sigma =
      1.0 / std::sqrt(2.0 * levels->navigation_dof);
  if (departure > std::max(kMinDepartureRatio,
                           1.0 + 3.0 * std::hypot(lag1->RelativeSigma(),
                                                  fit_relative_sigma))) {
    levels->warnings.push_back(fmt::format(
        "the images-only model departs from the navigation smoothly along the "
        "track: the residuals of their similarity are {:.3g}x the navigation's "
        "noise from one image to the next. The images bend the model, or tie "
        "the dives by few points, or the navigation drifts or is filtered "
        "(neighbours sharing their errors, which the differences miss){}; "
        "the noise "
        "level (and lambda) is the one from image to image, which a drift "
        "exceeds",
        departure,
        by_dive ? "" : ", or the dives are offset (--Dive.offsets 1)"));
  }
}

}  // namespace

NoiseLevels EstimateNoiseLevels(
    const NavBundleAdjustmentOptions& options,
    const std::vector<ImagePosePrior>& priors, const Reconstruction& model,
    const std::unordered_map<image_t, double>& image_times) {
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
  levels.fit_nav_scale = std::sqrt(chi2 / levels.navigation_dof);
  levels.nav_scale = levels.fit_nav_scale;
  ChooseDifferenceScale(linked, fit.residuals, image_times,
                        options.dive_offsets, &levels);
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
