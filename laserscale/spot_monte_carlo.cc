#include "laserscale/spot_monte_carlo.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/util/random.h"
#include "laserscale/spot_levels.h"

namespace uw::lsd {

const std::vector<float>& NormalQuantiles() {
  static const std::vector<float> table = [] {
    constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                            -2.759285104469687e+02, 1.383577518672690e+02,
                            -3.066479806614716e+01, 2.506628277459239e+00};
    constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                            -1.556989798598866e+02, 6.680131188771972e+01,
                            -1.328068155288572e+01};
    constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                            -2.400758277161838e+00, -2.549732539343734e+00,
                            4.374664141464968e+00,  2.938163982698783e+00};
    constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                            2.445134137142996e+00, 3.754408661907416e+00};
    const auto tail = [&](double q) {
      return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q +
              c[5]) /
             ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    };
    std::vector<float> values(1 << 16);
    for (size_t i = 0; i < values.size(); ++i) {
      const double p = (i + 0.5) / values.size();
      double x;
      if (p < 0.02425) {
        x = tail(std::sqrt(-2.0 * std::log(p)));
      } else if (p > 1.0 - 0.02425) {
        x = -tail(std::sqrt(-2.0 * std::log(1.0 - p)));
      } else {
        const double q = p - 0.5;
        const double r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r +
             a[5]) *
            q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r +
             1.0);
      }
      values[i] = static_cast<float>(x);
    }
    return values;
  }();
  return table;
}

cv::Mat WithNoise(const cv::Mat& image, double sigma, uint64_t key) {
  const std::vector<float>& quantiles = NormalQuantiles();
  cv::Mat noisy = image.clone();
  SplitMix64Stream random(key);
  const float s = static_cast<float>(sigma);
  for (int r = 0; r < noisy.rows; ++r) {
    float* row = noisy.ptr<float>(r);
    const int n = noisy.cols * 3;
    uint64_t bits = 0;
    for (int i = 0; i < n; ++i) {
      if (i % 4 == 0) bits = random.Next();
      row[i] += s * quantiles[bits & 0xFFFF];
      bits >>= 16;
    }
  }
  return noisy;
}

uint64_t IterationKey(uint64_t seed, size_t laser, int iteration) {
  return SplitMix64(SplitMix64(SplitMix64(seed) + laser) +
                    static_cast<uint64_t>(iteration));
}

double NoiseFromImage(const std::vector<Roi>& rois) {
  std::vector<float> values;
  for (const Roi& roi : rois) {
    if (roi.problem.empty()) AppendSecondDifferences(roi.main, &values);
  }
  return SecondDifferenceSigma(&values);
}

double NoiseFromDifference(const std::vector<Roi>& rois,
                           const SpotDetectorOptions& options) {
  std::vector<double> sigmas;
  for (const Roi& roi : rois) {
    if (!roi.problem.empty() || roi.aux.empty()) continue;
    const cv::Mat difference = Channel(roi.main, roi.colour.weakest) -
                               Channel(roi.aux, roi.colour.weakest);
    const double sigma = RobustStats(difference, roi.valid).sigma;
    sigmas.push_back(options.aux_equally_noisy
                         ? sigma / std::sqrt(1.0 + Square(roi.aux_noise_gain))
                         : sigma);
  }
  if (sigmas.empty()) return -1.0;
  std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2,
                   sigmas.end());
  return sigmas[sigmas.size() / 2];
}

void Merge(const std::vector<Detection>& detections, DetectedSpot* spot) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Detection& d : detections) mean += d.centre;
  mean /= static_cast<double>(detections.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const Detection& d : detections) {
    covariance +=
        d.centre_cov + (d.centre - mean) * (d.centre - mean).transpose();
  }
  spot->pixel = mean;
  spot->covariance = covariance / static_cast<double>(detections.size());
}

}  // namespace uw::lsd
