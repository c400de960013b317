// Choice of the navigation weight lambda by the L-curve (thesis ch. 4
// §5.2.1, [L3228-3236, L3627-3655]): run the adjustment for log-spaced
// lambdas, plot the two objectives in log-log space, and take the point of
// maximum curvature.
//
// Objectives (unweighted, so that they are comparable across lambdas):
//   rho(lambda) = mean |reprojection residual|^2 (px^2)
//   eta(lambda) = mean |camera centre - (prior + offset)|^2 (m^2)
// x = log10 rho, y = log10 eta, both functions of lambda. When the images
// alone give a deformed model (wrong distortion, scale drift, doming),
// small lambdas leave eta large, and raising lambda first removes the
// deformation at little cost in rho (the curve descends), then fits the
// navigation noise at a growing cost in rho (it runs to the right). The
// corner is the largest counter-clockwise curvature d theta / d length of
// the curve, with the tangent angle theta smoothed over 5 % of the curve's
// length (so that nearly stationary ends, where an objective has reached
// its floor, do not count as corners); lambda there is interpolated along
// the curve. At the corner both objectives sit near their noise floors, so
// lambda^2 ~ rho / eta ~ (2 sigma_v^2) / (3 sigma_n^2): the thesis's
// lambda = sigma_v / sigma_n. A model the images do not deform has no
// descending branch and hence no corner; the balance point below exists
// either way.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "colmap_plugins/ba/nav_bundle_adjuster.h"
#include "common/util/figure.h"

namespace uw {

struct LCurvePoint {
  double weight_px_per_m = 0.0;
  double reprojection_ms_px2 = 0.0;
  double navigation_ms_m2 = 0.0;
  std::optional<double> curvature;
};

struct LCurve {
  std::vector<LCurvePoint> points;
  // The largest counter-clockwise turn; absent when the curve never turns
  // that way (no descending branch).
  std::optional<size_t> corner_index;
  std::optional<double> corner_weight_px_per_m;  // interpolated along it
  // The balance point: lambda^2 = (rho / 2) / (eta / 3), where the per-
  // coordinate objectives stand in the ratio Eq. 2 weighs them by. With
  // both at their noise floors this is sigma_v / sigma_n; on the L-curve
  // it is where the tangent slope d log eta / d log rho = -rho / (lambda^2
  // eta) is -2/3. Unlike the corner it exists when the images alone do not
  // deform the model (no descending branch). Interpolated in log lambda;
  // absent if the sweep does not cross it.
  std::optional<double> balance_weight_px_per_m;
  // lambda from the estimated noise levels (noise_levels.h), when the
  // caller has it: marked on the plot and written to the JSON.
  std::optional<double> noise_weight_px_per_m;
};

// count values from min to max, equally spaced in log.
std::vector<double> LogSpacedWeights(double min, double max, int count);

// Curvature of each point, the corner and the balance point. Points must be
// sorted by weight, at least 5, with positive finite objectives that change
// with the weight; throws uw::Error otherwise.
LCurve FindLCurveCorner(std::vector<LCurvePoint> points);

// Runs AdjustWithNavigation on a copy of `model` for every weight, each
// start warm from the previous weight's solution (weights in the given
// order), and finds the corner. `progress(i, n, point)` after each solve.
LCurve SweepLCurve(
    const NavBundleAdjustmentOptions& options,
    const std::vector<ImagePosePrior>& priors, const SoftRig* rig,
    const std::unordered_map<image_t, double>& image_times,
    const Reconstruction& model, const std::vector<double>& weights,
    const std::function<void(size_t, size_t, const LCurvePoint&)>& progress =
        nullptr);

// The L-curve as JSON text, and as figures (common/util/figure.h): the
// log-log objectives with the corner marked, and the curvature against
// lambda with the corner, balance and noise-level weights, written as
// LCurveFigurePaths(folder).
std::string LCurveJson(const LCurve& curve);
std::vector<Figure> LCurveFigures(const LCurve& curve);
// folder/lcurve.png and folder/lcurve_curvature.png (each with its .svg).
std::vector<std::filesystem::path> LCurveFigurePaths(
    const std::filesystem::path& folder);

}  // namespace uw
