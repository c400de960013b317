// The two noise levels of Eq. 1 estimated from the data, and the weight
// lambda = sigma_v / sigma_n they imply (`--Nav.weight auto`).
//
// Variance components at the images-only end of the L-curve (lambda -> 0):
// there the images alone shape the model and the navigation only places
// it (a similarity, plus one offset per extra dive), so the degrees of
// freedom of each residual group are exact:
//   sigma_v^2 = sum |r_v|^2 / (2M - (3P + 6N - 7 + K))   (px^2 per coordinate)
//   s_n^2     = sum |S_i e_i|^2 / (3N_p - 7 - 3(D - 1))   (unitless)
// r_v: reprojection residuals of the images-only adjustment (M
// observations, P points, N images, K free intrinsics); e_i: camera centre
// minus prior after the covariance-weighted similarity (and dive offsets),
// S_i the whitening of the prior's covariance; D dives. s_n is the factor by
// which the priors' stated sigmas are off, so the navigation noise is
// sigma_n = s_n * NavSigma(priors) and Eq. 2's weight is
// lambda = sigma_v / sigma_n.
//
// Why not the L-curve's corner: the corner is a property of the plot's
// shape, not of the noise; on synthetic surveys with known noise it lies
// 1.05-2.8x from sigma_v / sigma_n, and where the navigation is about as
// precise as the images Eq. 2's normalisation (priors weighted M/N times a
// likelihood) keeps the curve from showing a balance of the two noise
// floors at all. The estimate above is what the L-curve's ends converge
// to, with the degrees of freedom the fitted parameters take away (the
// naive per-coordinate mean squares give 0.8x).
//
// A model the images deform (a long strip that bends, dives tied by few
// points) is not a similarity of the truth: its departure inflates e_i,
// and the similarity's s_n counted it as navigation noise (1.8-2x the
// realised noise on uwsim's seafloor and canyon), which made lambda too
// small to let the navigation straighten the model. With the images'
// times (`image_times`), s_n is therefore the second differences' of the
// e_i along each dive instead (difference_noise.h), which no smooth
// departure reaches; the similarity's s_n is kept, and a departure beyond
// its noise warned of, as is a log whose neighbouring images share their
// errors (interpolated between fixes), where s_n stays the similarity's.
// Without times, or with fewer than 10 differences, s_n is the
// similarity's.
#pragma once

#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "colmap_plugins/scene/model.h"

namespace uw {

struct NoiseLevels {
  double pixel_sigma = 0.0;  // sigma_v, px per image coordinate
  double nav_scale = 0.0;    // s_n: observed / stated prior sigma
  // The two estimates s_n is chosen from: the similarity's residuals
  // (above), and their second differences along each dive at lags 1 and 2
  // (difference_noise.h; 0 without image times or with too few images).
  double fit_nav_scale = 0.0;
  double difference_nav_scale = 0.0;
  double difference_lag2_nav_scale = 0.0;
  double stated_nav_sigma_m = 0.0;  // NavSigma(priors)
  double nav_sigma_m = 0.0;         // sigma_n = s_n * stated, m
  double weight_px_per_m = 0.0;     // lambda = sigma_v / sigma_n
  double reprojection_dof = 0.0;
  double navigation_dof = 0.0;
  // With options.dive_offsets: each dive's offset (added to its priors) in
  // the least-squares fit above, relative to the reference dive, or to the
  // lowest dive left when the reference dive's images were left out; dives
  // all of whose images were left out are missing. The adjuster does not
  // read them (it fits its own start, nav_bundle_adjuster.cc).
  std::map<int, Eigen::Vector3d> dive_offsets;
  // The images-only adjustment's warnings (an unconverged solve above
  // all): the estimates come from its model.
  std::vector<std::string> warnings;
};

// Runs the images-only adjustment (options' intrinsics and loss, no priors,
// no rig) on a copy of `model`, aligns it to the priors and returns the
// estimates. `image_times` (seconds, the navigation's clock) orders each
// dive's priors for the differences. Throws uw::Error when a group has no
// degrees of freedom left or the alignment fails (fewer than 3 or collinear
// priors).
NoiseLevels EstimateNoiseLevels(
    const NavBundleAdjustmentOptions& options,
    const std::vector<ImagePosePrior>& priors, const Reconstruction& model,
    const std::unordered_map<image_t, double>& image_times = {});

}  // namespace uw
