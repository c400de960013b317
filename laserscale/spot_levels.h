// The levels the spot detector measures on its patches (CV_32F, 8-bit
// units): a robust level and spread, one channel, the low-pass against
// noise and compression artefacts and its noise gain, V, and where a
// channel clips.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "laserscale/spot_detector_options.h"

namespace uw::lsd {

// MAD of a Gaussian = 0.6745 σ.
constexpr double kMadToSigma = 1.4826;

inline double Square(double x) { return x * x; }

// A background level and the robust σ around it.
struct RobustLevel {
  double median = 0.0;
  double sigma = 0.0;
};

// Median and MAD-based σ of the values of `image` (CV_32F) under `mask`
// (CV_8U), from a regular subsample of a few thousand pixels: plenty for a
// level and a spread, and a fraction of the cost on large patches. Zeros
// when the mask is empty.
RobustLevel RobustStats(const cv::Mat& image, const cv::Mat& mask);

cv::Mat Channel(const cv::Mat& image, int channel);

// LSD step 6: a Gaussian blur of `sigma` px (none for sigma <= 0).
cv::Mat LowPass(const cv::Mat& image, double sigma);

// The σ of white noise after LowPass, per unit σ before: the L2 norm of the
// (separable) kernel.
double LowPassNoiseGain(const SpotDetectorOptions& options);

// The absolute responses of `patch` (CV_32F, any channels) to the 3x3
// second difference [1 -2 1; -2 4 -2; 1 -2 1], appended to `values`: white
// noise of σ gives responses of σ 6 (the weights square-sum to 36), and
// smooth texture almost none.
void AppendSecondDifferences(const cv::Mat& patch, std::vector<float>* values);

// The noise σ from those responses, their MAD / 6 (robust to the few large
// ones of texture edges); 0 for none. Reorders `values`.
double SecondDifferenceSigma(std::vector<float>* values);

// V (the largest channel) of a CV_32FC3 image.
cv::Mat ValueImage(const cv::Mat& image);

// Where channel c of `levels` (CV_32FC3) is clipped, grown by the
// low-pass's reach: CV_8U, 255 there.
cv::Mat Clipped(const cv::Mat& levels, int c,
                const SpotDetectorOptions& options);

}  // namespace uw::lsd
