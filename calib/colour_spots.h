// Laser spots on calibration boards: compact blobs of the laser's colour.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace uw {

struct ColourSpotOptions {
  // The laser's colour (linear RGB, as lasers.json stores it). A pixel's
  // score is its RGB levels weighted by colour - mean(colour): grey of any
  // level scores 0, the laser's colour most.
  Eigen::Vector3d colour{1.0, 0.0, 0.0};
  // A spot: 8-connected pixels whose score exceeds the median of a
  // background_window_px square around them by min_excess levels, of
  // min_area_px to max_area_px pixels.
  double min_excess = 20.0;
  int background_window_px = 31;
  int min_area_px = 3;
  int max_area_px = 2000;

  void Check() const;  // throws uw::Error naming the field
};

// The spots' centres (COLMAP's pixel convention: the top-left pixel's
// centre is (0.5, 0.5)): each component's centroid weighted by its excess.
// 8-bit BGR.
std::vector<Eigen::Vector2d> FindColourSpots(const cv::Mat& bgr,
                                             const ColourSpotOptions& options);

}  // namespace uw
