// Laser-spot detection with uncertainty (ch4 spec §5;
// docs/laserscale_detector.md): per laser, a region of interest predicted from
// the calibrated beam, the texture removed with an auxiliary image (FFT
// normalised cross-correlation, ECC homography, histogram matching,
// subtraction), a colour threshold in HSV, the brightest connected component
// near the beam's image, and an elliptical Gaussian fitted to it (LSD, §5.2). A
// Monte Carlo over image noise (LSD-MC, §5.3) tells whether the detection is
// stable and gives the covariance of its centre.
//
// Pixels follow COLMAP's convention: the upper-left image corner is (0, 0),
// the centre of pixel (c, r) is (c + 0.5, r + 0.5). Levels are those of the
// 8-bit image (0-255), as encoded by the camera.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "colmap_plugins/scene/model.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spot_detector_options.h"

namespace uw {

struct DetectedSpot {
  std::string laser;  // laser name from the set-up
  // Found by the nominal (noise-free) detection.
  bool detected = false;
  // Detected, and in >= min_detection_rate of the Monte Carlo iterations:
  // confident; only these go to the scale.
  bool stable = false;
  double detection_rate = 0.0;
  // Merged centre (COLMAP pixel convention) and its covariance (px^2): the
  // moments of the mixture of the iterations' N(centre, Σc). Zero when not
  // detected.
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  // Each successful Monte Carlo iteration's centre and Σc (for overlays).
  std::vector<std::pair<Eigen::Vector2d, Eigen::Matrix2d>> iterations;
  // Why not detected or not stable, e.g. "outside the image", "not
  // detected", "unstable: detected in 43 % of iterations"; empty otherwise.
  std::string problem;
};

// Detects every laser of `setup` in `image`. image, aux: 8-bit BGR (as
// cv::imread gives) of the camera's size; aux may be empty (no texture
// removal). `camera` is the image's COLMAP camera, `setup` the calibrated
// lasers (ROI prediction and colours). Results are in the set-up's laser
// order and depend only on the inputs and the seed. Throws uw::Error for
// bad inputs (empty or non-BGR images, sizes that differ from the camera's,
// invalid options or set-up).
std::vector<DetectedSpot> DetectSpots(const cv::Mat& image, const cv::Mat& aux,
                                      const Camera& camera,
                                      const LaserSetup& setup,
                                      const SpotDetectorOptions& options,
                                      uint64_t seed);

// Baseline: the brightest pixel in the laser's colour channel among the
// ROI's pixels that pass the hue test (options' hue_tolerance_deg and
// min_saturation) on the laser's beam; the centre of all of them where
// several tie (a clipped spot is a plateau). No texture removal, no fit, no
// Monte Carlo; the covariance is that of a uniform position within a pixel,
// I/12.
std::vector<DetectedSpot> DetectBrightestPixel(
    const cv::Mat& image, const Camera& camera, const LaserSetup& setup,
    const SpotDetectorOptions& options);

}  // namespace uw
