// LSD steps 7-9: the pixels of a texture-removed ROI bright enough (and of
// the laser's hue) to be a spot, and the connected component that is the
// laser's spot.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "laserscale/spot_colour.h"
#include "laserscale/spot_detector_options.h"

namespace uw::lsd {

// The opened colour mask of LSD step 7-8: pixels of the low-passed
// `clean` image (CV_32FC3) of the laser's hue, saturated enough and at
// least `min_value` bright.
// `valid` (CV_8U) limits it; opened with a disc of opening_radius_px.
cv::Mat ColourMask(const cv::Mat& clean, const cv::Mat& valid,
                   const LaserColour& colour, double min_value,
                   const SpotDetectorOptions& options);

// LSD step 9: the component of `mask` with the largest summed V (of
// `clean`) whose centroid lies on beam `own` of `beams` (OnOwnBeam).
// Returns its mask, empty if there is none. `rivals` receives the bounding
// box of it and of the candidates whose summed V is at least
// kRivalFraction of its: those that noise could make win.
constexpr double kRivalFraction = 0.25;
cv::Mat BestComponent(const cv::Mat& mask, const cv::Mat& clean,
                      const std::vector<std::vector<Eigen::Vector2d>>& beams,
                      size_t own, const SpotDetectorOptions& options,
                      cv::Rect* rivals);

}  // namespace uw::lsd
