// Synthetic laser images for the spot detector's unit tests: one spot
// drawn at a known sub-pixel position on a flat or textured background, the
// detector's maths without the renderer.
#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_setup.h"

namespace uw {

// A pinhole camera with its principal point at the image centre.
Camera PinholeCamera(int width, int height, double focal);

// One red laser 10 cm right of the camera, parallel to its axis: with the
// 320x240 camera below its beam's image runs along y = 120 from x = 200
// (1 m) to x = 166.7 (6 m).
LaserSetup OneLaser();

// A textured background: smooth random blobs, 20-120 levels, greenish.
cv::Mat Texture(int width, int height, uint64_t seed);

// `background` (CV_32FC3) plus a red elliptical Gaussian spot at `centre`
// (COLMAP convention) with peak `amplitude` and covariance `shape`, plus
// noise of `sigma`, clipped and rounded to 8 bits.
cv::Mat WithSpot(const cv::Mat& background, const Eigen::Vector2d& centre,
                 double amplitude, const Eigen::Matrix2d& shape, double sigma,
                 uint64_t seed);

// A flat greenish background (CV_32FC3).
cv::Mat Flat(int width, int height);

}  // namespace uw
