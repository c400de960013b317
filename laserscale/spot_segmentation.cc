#include "laserscale/spot_segmentation.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "laserscale/beam_image.h"

namespace uw::lsd {

cv::Mat ColourMask(const cv::Mat& clean, const cv::Mat& valid,
                   const LaserColour& colour, double min_value,
                   const SpotDetectorOptions& options) {
  cv::Mat mask(clean.size(), CV_8U, cv::Scalar(0));
  for (int r = 0; r < clean.rows; ++r) {
    const cv::Vec3f* row = clean.ptr<cv::Vec3f>(r);
    const uint8_t* ok = valid.ptr<uint8_t>(r);
    uint8_t* out = mask.ptr<uint8_t>(r);
    for (int c = 0; c < clean.cols; ++c) {
      if (!ok[c]) continue;
      const cv::Vec3f& bgr = row[c];
      const double value = std::max({bgr[0], bgr[1], bgr[2]});
      if (!(value >= min_value && value > 0.0)) continue;
      if (colour.chromatic) {
        const double saturation =
            (value - std::min({bgr[0], bgr[1], bgr[2]})) / value;
        if (saturation < options.min_saturation) continue;
        if (HueDistanceDeg(HueDeg(bgr[2], bgr[1], bgr[0]), colour.hue_deg) >
            options.hue_tolerance_deg) {
          continue;
        }
      }
      out[c] = 255;
    }
  }
  if (options.opening_radius_px > 0) {
    const int size = 2 * options.opening_radius_px + 1;
    cv::morphologyEx(
        mask, mask, cv::MORPH_OPEN,
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
  }
  return mask;
}

cv::Mat BestComponent(const cv::Mat& mask, const cv::Mat& clean,
                      const std::vector<std::vector<Eigen::Vector2d>>& beams,
                      size_t own, const SpotDetectorOptions& options,
                      cv::Rect* rivals) {
  cv::Mat labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int count =
      cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
  if (count <= 1) return {};
  std::vector<double> summed_value(count, 0.0);
  for (int r = 0; r < labels.rows; ++r) {
    const int* label = labels.ptr<int>(r);
    const cv::Vec3f* row = clean.ptr<cv::Vec3f>(r);
    for (int c = 0; c < labels.cols; ++c) {
      if (label[c] > 0) {
        summed_value[label[c]] += std::max({row[c][0], row[c][1], row[c][2]});
      }
    }
  }
  std::vector<int> candidates;
  int best = 0;
  for (int k = 1; k < count; ++k) {
    const int area = stats.at<int>(k, cv::CC_STAT_AREA);
    if (area < options.min_area_px || area > options.max_area_px) continue;
    // Pixel centres are at +0.5 in the COLMAP convention.
    const Eigen::Vector2d centroid(centroids.at<double>(k, 0) + 0.5,
                                   centroids.at<double>(k, 1) + 0.5);
    if (!OnOwnBeam(centroid, beams, own, options.roi_margin_px)) continue;
    candidates.push_back(k);
    if (best == 0 || summed_value[k] > summed_value[best]) best = k;
  }
  if (best == 0) return {};
  const auto box = [&](int k) {
    return cv::Rect(stats.at<int>(k, cv::CC_STAT_LEFT),
                    stats.at<int>(k, cv::CC_STAT_TOP),
                    stats.at<int>(k, cv::CC_STAT_WIDTH),
                    stats.at<int>(k, cv::CC_STAT_HEIGHT));
  };
  *rivals = box(best);
  for (const int k : candidates) {
    if (summed_value[k] >= kRivalFraction * summed_value[best]) {
      *rivals |= box(k);
    }
  }
  cv::Mat component;
  cv::compare(labels, best, component, cv::CMP_EQ);
  return component;
}

}  // namespace uw::lsd
