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
// of magnified crops around each spot, where sub-pixel ellipses are
// legible. Marks, text and the crops' magnification (8x) grow with the
// image beyond 1500 px wide (x2 at 2250 px, x4 at 5250: a 27 MP frame), so
// that they stay visible when the whole frame is viewed or shrunk.
cv::Mat DrawSpotOverlay(const cv::Mat& image,
                        const std::vector<DetectedSpot>& spots);

}  // namespace uw
