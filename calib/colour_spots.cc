#include "calib/colour_spots.h"

#include <opencv2/imgproc.hpp>

#include "common/util/error.h"

namespace uw {

void ColourSpotOptions::Check() const {
  if (!colour.allFinite() ||
      (colour - Eigen::Vector3d::Constant(colour.mean())).norm() < 1e-6) {
    throw Error("colour spots: colour must be finite and not grey");
  }
  if (!(min_excess > 0.0)) throw Error("colour spots: min_excess must be > 0");
  if (background_window_px < 3 || background_window_px % 2 == 0) {
    throw Error("colour spots: background_window_px must be odd and >= 3");
  }
  if (min_area_px < 1 || max_area_px < min_area_px) {
    throw Error("colour spots: need 1 <= min_area_px <= max_area_px");
  }
}

std::vector<Eigen::Vector2d> FindColourSpots(const cv::Mat& bgr,
                                             const ColourSpotOptions& options) {
  options.Check();
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    throw Error("colour spots: the image must be 8-bit BGR");
  }
  const Eigen::Vector3d weight =
      options.colour - Eigen::Vector3d::Constant(options.colour.mean());
  const Eigen::Vector3d unit = weight / weight.norm();
  cv::Mat score(bgr.size(), CV_32F);
  for (int r = 0; r < bgr.rows; ++r) {
    for (int c = 0; c < bgr.cols; ++c) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(r, c);
      score.at<float>(r, c) = static_cast<float>(
          unit.x() * p[2] + unit.y() * p[1] + unit.z() * p[0]);
    }
  }
  // The median of a large window is the board's own colour there: the
  // excess is the laser's light alone (medianBlur takes 8 bits beyond 5x5).
  cv::Mat shifted;
  score.convertTo(shifted, CV_8U, 1.0, 128.0);
  cv::Mat background;
  cv::medianBlur(shifted, background, options.background_window_px);
  cv::Mat background_score;
  background.convertTo(background_score, CV_32F, 1.0, -128.0);
  const cv::Mat excess = score - background_score;
  cv::Mat mask = excess > options.min_excess;
  cv::Mat labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int count =
      cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
  std::vector<Eigen::Vector2d> spots;
  for (int label = 1; label < count; ++label) {
    const int area = stats.at<int>(label, cv::CC_STAT_AREA);
    if (area < options.min_area_px || area > options.max_area_px) continue;
    const int x0 = stats.at<int>(label, cv::CC_STAT_LEFT);
    const int y0 = stats.at<int>(label, cv::CC_STAT_TOP);
    const int w = stats.at<int>(label, cv::CC_STAT_WIDTH);
    const int h = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    double sum = 0.0;
    Eigen::Vector2d moment = Eigen::Vector2d::Zero();
    for (int r = y0; r < y0 + h; ++r) {
      for (int c = x0; c < x0 + w; ++c) {
        if (labels.at<int>(r, c) != label) continue;
        const double e = excess.at<float>(r, c);
        sum += e;
        moment += e * Eigen::Vector2d(c + 0.5, r + 0.5);
      }
    }
    if (sum > 0.0) spots.push_back(moment / sum);
  }
  return spots;
}

}  // namespace uw
