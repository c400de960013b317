#include "laserscale/gaussian_spot_fit.h"

#include <Eigen/LU>

namespace uw::lsd {

bool FitSpot(const FitSamples& samples, double background,
             const GaussianSpot& start, const PrintGeometry& geometry,
             GaussianSpot* spot, GaussianSpot* print) {
  const Eigen::Matrix2d start_precision = start.covariance.inverse();
  const auto run = [&](auto fit) {
    using Fit = decltype(fit);
    typename Fit::Vector theta;
    theta(0) = background;
    theta(1) = start_precision(0, 0);
    theta(2) = start_precision(0, 1);
    theta(3) = start_precision(1, 1);
    theta(4) = start.amplitude;
    theta.template segment<2>(5) = start.mean;
    if constexpr (Fit::kParams == 9) {
      theta(7) = print->amplitude;
      theta(8) =
          (print->mean - start.mean - geometry.offset).dot(geometry.along);
    }
    if (!fit.Fit(samples, &theta)) return false;
    Eigen::Matrix2d precision;
    precision << theta(1), theta(2), theta(2), theta(3);
    spot->amplitude = theta(4);
    spot->mean = theta.template segment<2>(5);
    spot->covariance = precision.inverse();
    if constexpr (Fit::kParams == 9) {
      print->amplitude = theta(7);
      print->mean = fit.PrintMean(theta);
      print->covariance = spot->covariance;
    }
    return true;
  };
  if (print == nullptr) return run(SpotFit<false>());
  SpotFit<true> fit;
  fit.geometry = geometry;
  return run(fit);
}

void AddSamples(const cv::Mat& window, const cv::Mat& signal,
                const cv::Mat& lower, const cv::Mat& upper,
                FitSamples* samples) {
  for (int r = 0; r < window.rows; ++r) {
    const uint8_t* in = window.ptr<uint8_t>(r);
    const float* value = signal.ptr<float>(r);
    for (int c = 0; c < window.cols; ++c) {
      if (!in[c]) continue;
      const bool is_lower = !lower.empty() && lower.at<uint8_t>(r, c);
      const bool is_upper = !upper.empty() && upper.at<uint8_t>(r, c);
      if (is_lower && is_upper) continue;
      samples->xs.emplace_back(c + 0.5, r + 0.5);
      samples->ys.push_back(value[c]);
      samples->bounds.push_back(is_lower ? 1 : is_upper ? -1 : 0);
    }
  }
}

}  // namespace uw::lsd
