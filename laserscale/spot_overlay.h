// What the spot detector found, drawn on its image for a person to check
// (docs/laserscale_detector.md, "Reading the overlay").
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "laserscale/spot_detector.h"

namespace uw {

// The image with each stable spot's merged 68 % and 95 % ellipses
// (Mahalanobis radii 1.510 and 2.448), the iterations' centres faintly, and
// unstable or undetected lasers marked with their reason; below it a strip
// of 8x magnified crops around each spot, where sub-pixel ellipses are
// legible.
cv::Mat DrawSpotOverlay(const cv::Mat& image,
                        const std::vector<DetectedSpot>& spots);

}  // namespace uw
