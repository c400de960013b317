// LSD-MC (ch4 spec §5.3-5.4): the noise the Monte Carlo adds to a ROI's
// image, the image noise it is drawn with when not given (§5.4), and the
// merge of the iterations' detections into one centre and covariance.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "laserscale/spot_detector.h"
#include "laserscale/spot_roi.h"

namespace uw::lsd {

// One detection's centre (image pixels, COLMAP convention) and the
// covariance Σc of the centre given its spot's shape.
struct Detection {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // image coordinates
  Eigen::Matrix2d centre_cov = Eigen::Matrix2d::Zero();
};

// Standard normal quantiles at (i + 0.5) / 2^16 (Acklam's rational
// approximation, relative error < 1.2e-9): the Monte Carlo's noise takes
// four 16-bit indices from each SplitMix64 draw, ~20x cheaper than
// Box-Muller, with tails cut at 4.2 σ (probability 3e-5).
const std::vector<float>& NormalQuantiles();

// `image` (CV_32FC3) plus i.i.d. N(0, sigma^2) in every channel, from the
// counter-based key (so any thread gives the same noise).
cv::Mat WithNoise(const cv::Mat& image, double sigma, uint64_t key);

// The key of iteration `iteration` of laser `laser` for a detection's seed.
uint64_t IterationKey(uint64_t seed, size_t laser, int iteration);

// §5.4 without an aux: robust σ of the image's second differences
// (Immerkær's 3x3 operator, whose response to white noise has σ 6 σ_pixel),
// in the ROIs; edges of the texture are outliers that the median ignores.
// 0 without a ROI to measure.
double NoiseFromImage(const std::vector<Roi>& rois);

// §5.4 with the aux: robust σ of the aligned, matched difference in the
// laser's weakest channel; when both frames are equally noisy, that is
// σ sqrt(1 + g^2) with g the aligned aux's noise gain. The median over the
// ROIs.
// < 0 without a ROI that has an aux.
double NoiseFromDifference(const std::vector<Roi>& rois,
                           const SpotDetectorOptions& options);

// Moments of the mixture of the detections' N(centre, Σc) (§5.3 step 4:
// equal to the Unscented Transform's merge of their sigma points).
// Sets spot->pixel and spot->covariance; `detections` is not empty.
void Merge(const std::vector<Detection>& detections, DetectedSpot* spot);

}  // namespace uw::lsd
