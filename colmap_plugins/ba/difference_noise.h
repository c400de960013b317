// The white noise of a navigation log from the second differences of its
// residuals along each dive, blind to what varies smoothly along the track.
//
// The residuals e_i of the images-only model's similarity to the priors
// (noise_levels.h) hold the navigation's noise and the model's own error:
// a model the images bend (a long strip), or dives the images tie by a few
// points, is not a similarity of the truth, and its departure counts as
// navigation noise there (sigma_n 1.8-2x the realised noise on uwsim's
// seafloor and canyon). That departure varies smoothly along the track;
// white navigation noise does not. Each image's residual, less the line
// through its neighbours `lag` samples before and after it in time
// (Gasser, Sroka and Jennen-Steinmetz 1986, "Residual variance and
// residual pattern in nonlinear regression", Biometrika 73(3)):
//   d_i = a e_{i-k} + b e_{i+k} - e_i,  a = (t_{i+k} - t_i) / (t_{i+k} -
//   t_{i-k}), b = 1 - a Cov(d_i) = s^2 (a^2 C_{i-k} + b^2 C_{i+k} + C_i)
// so s^2 = mean_i d_i' (a^2 C_{i-k} + b^2 C_{i+k} + C_i)^-1 d_i / 3, where
// C_i is prior i's stated covariance and s the factor by which the stated
// sigmas are off. A straight line through the neighbours removes the
// similarity, the offsets and any trend to first order, so no degree of
// freedom is taken by the fit.
//
// It measures the noise that changes from one image to the next. A log
// interpolated between sparse fixes, or smoothed by a filter, has errors
// that its neighbours share, which no difference sees: the estimate at lag
// 2 then exceeds the one at lag 1 (noise_levels.cc falls back to the
// similarity's residuals then). What varies smoothly in the navigation's
// errors (a DVL's drift) is not in s either: noise_levels.cc warns when
// the similarity's residuals exceed it. Images taken at one time (a rig) share
// one navigation sample: only the first of them is used.
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace uw {

struct TimedResidual {
  int dive = 1;
  double time_s = 0.0;
  Eigen::Vector3d residual = Eigen::Vector3d::Zero();        // m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // stated, m^2
};

struct DifferenceNoise {
  double scale = 0.0;  // s: observed / stated sigma
  int num_differences = 0;

  // The standard deviation of `scale` over its value under white noise:
  // each whitened coordinate of d_i squared has variance 2 s^4, and
  // neighbouring differences correlate by -2/3 (lag 1 apart) and 1/6 (2
  // apart) at even spacing, so the mean of 3n squares has variance
  // 2 s^4 (1 + 2 (4/9) + 2 (1/36)) / (3n) = 1.296 s^4 / n, and
  // sd(s) / s = 0.569 / sqrt(n).
  double RelativeSigma() const {
    return 0.569 / std::sqrt(static_cast<double>(num_differences));
  }
};

// s from the differences at `lag` (>= 1) over every dive, or nullopt when
// fewer than `min_differences` can be formed (at 10, s is known to 18 %).
// Throws uw::Error when lag < 1 or a covariance is not positive definite.
std::optional<DifferenceNoise> EstimateDifferenceNoise(
    std::vector<TimedResidual> residuals, int lag, int min_differences = 10);

}  // namespace uw
