#include "laserscale/spot_levels.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace uw::lsd {
namespace {

// Pixels that RobustStats samples at most (about).
constexpr size_t kRobustSamples = 4096;

}  // namespace

RobustLevel RobustStats(const cv::Mat& image, const cv::Mat& mask) {
  const size_t stride = std::max<size_t>(1, image.total() / kRobustSamples);
  std::vector<float> values;
  values.reserve(image.total() / stride + 1);
  size_t index = 0;
  for (int r = 0; r < image.rows; ++r) {
    const float* row = image.ptr<float>(r);
    const uint8_t* m = mask.ptr<uint8_t>(r);
    for (int c = 0; c < image.cols; ++c, ++index) {
      if (index % stride == 0 && m[c]) values.push_back(row[c]);
    }
  }
  if (values.empty()) return {};
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  const double median = *middle;
  for (float& v : values) v = std::abs(v - static_cast<float>(median));
  std::nth_element(values.begin(), middle, values.end());
  return {median, kMadToSigma * *middle};
}

cv::Mat Channel(const cv::Mat& image, int channel) {
  cv::Mat out;
  cv::extractChannel(image, out, channel);
  return out;
}

double LowPassNoiseGain(const SpotDetectorOptions& options) {
  if (options.lowpass_sigma_px <= 0.0) return 1.0;
  // GaussianBlur's kernel size for float images.
  const cv::Mat kernel =
      cv::getGaussianKernel(cvRound(options.lowpass_sigma_px * 8.0 + 1.0) | 1,
                            options.lowpass_sigma_px, CV_64F);
  return Square(cv::norm(kernel));
}

cv::Mat LowPass(const cv::Mat& image, double sigma) {
  if (sigma <= 0.0) return image;
  cv::Mat out;
  cv::GaussianBlur(image, out, cv::Size(0, 0), sigma, sigma,
                   cv::BORDER_REPLICATE);
  return out;
}

void AppendSecondDifferences(const cv::Mat& patch, std::vector<float>* values) {
  const cv::Mat kernel =
      (cv::Mat_<float>(3, 3) << 1, -2, 1, -2, 4, -2, 1, -2, 1);
  cv::Mat response;
  cv::filter2D(patch, response, CV_32F, kernel, cv::Point(-1, -1), 0,
               cv::BORDER_REPLICATE);
  const cv::Mat flat = response.reshape(1, 1);
  for (int i = 0; i < flat.cols; ++i) {
    values->push_back(std::abs(flat.at<float>(0, i)));
  }
}

double SecondDifferenceSigma(std::vector<float>* values) {
  if (values->empty()) return 0.0;
  const auto middle = values->begin() + values->size() / 2;
  std::nth_element(values->begin(), middle, values->end());
  return kMadToSigma * *middle / 6.0;
}

cv::Mat ValueImage(const cv::Mat& image) {
  std::vector<cv::Mat> channels;
  cv::split(image, channels);
  cv::Mat value = cv::max(channels[0], channels[1]);
  return cv::max(value, channels[2]);
}

cv::Mat Clipped(const cv::Mat& levels, int c,
                const SpotDetectorOptions& options) {
  const int reach = static_cast<int>(std::ceil(3.0 * options.lowpass_sigma_px));
  cv::Mat mask;
  cv::compare(Channel(levels, c), options.saturation_level, mask, cv::CMP_GE);
  cv::dilate(mask, mask,
             cv::getStructuringElement(cv::MORPH_ELLIPSE,
                                       cv::Size(2 * reach + 1, 2 * reach + 1)));
  return mask;
}

}  // namespace uw::lsd
