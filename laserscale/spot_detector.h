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

namespace uw {

struct SpotDetectorOptions {
  // 1. ROI: each beam's points at depths (camera z) from min_range_m to
  // max_range_m, projected; their bounding box grown by roi_margin_px. A
  // spot is accepted only within roi_margin_px of that projected segment
  // (calibration error plus spot radius) and no nearer another beam's,
  // which also tells the lasers apart.
  double min_range_m = 1.0;
  double max_range_m = 6.0;
  int roi_margin_px = 24;

  // 2-5. Texture removal with the auxiliary image: the ROI is found in it
  // by FFT normalised cross-correlation within aux_search_px of its place
  // (the camera moved between the frames), refined by an ECC homography
  // (at most ecc_iterations), matched per channel by histogram, and
  // subtracted. Below min_alignment_ncc the texture is not removed in that
  // ROI (the aux does not show the same scene).
  bool texture_removal = true;
  int aux_search_px = 64;
  double min_alignment_ncc = 0.5;
  int ecc_iterations = 50;

  // 6. Gaussian low-pass against noise and compression artefacts.
  double lowpass_sigma_px = 1.0;

  // 7. HSV threshold on the increments over the ROI's median (per channel)
  // of the texture-removed image (of the image without an aux): V >= the
  // increments' median + value_threshold_sigmas robust σ (the nominal one
  // and the Monte Carlo noise in quadrature; and >= min_value levels). The
  // hue test (within hue_tolerance_deg of the laser colour's hue, red
  // wrapping at 0/360, for saturation >= min_saturation) is off by default:
  // in uwsim's water a red laser's green and blue leak outlive its red, so
  // its spots turn from red at 1.5 m to green at 4 m (docs). On real red
  // lasers, whose light stays red, 30-40 deg and 0.3 reject other colours.
  double hue_tolerance_deg = 180.0;
  double min_saturation = 0.0;
  double value_threshold_sigmas = 4.0;
  double min_value = 2.0;

  // 8-9. Opening with a disc of opening_radius_px (removes isolated noise
  // pixels), 8-connected components of min_area_px to max_area_px pixels;
  // per ROI the one with the largest summed V on the laser's beam wins.
  int opening_radius_px = 1;
  int min_area_px = 3;
  int max_area_px = 4000;

  // 10-11. The Gaussian is fitted to the channel in which the component is
  // brightest (V's channel on the spot) over the component grown by
  // fit_margin_px (its tails and background). Pixels at or above
  // saturation_level, and their low-passed neighbours, bound the fit
  // instead of fixing it (censored least squares), so a clipped top still
  // tells how high the spot is.
  int fit_margin_px = 3;
  double saturation_level = 250.0;

  // 12. Centre covariance from the spot's shape, thesis reading: the centre
  // lies within the top `top_fraction` of the spot's luminance with
  // probability `confidence`, i.e. Σc = Σb · 2 ln(1 / (1 - top_fraction)) /
  // (-2 ln(1 - confidence)) = 0.0745 Σb for the thesis's 20 % / 95 %.
  double top_fraction = 0.20;
  double confidence = 0.95;

  // LSD-MC (§5.3): iterations with i.i.d. Gaussian noise of noise_sigma
  // added to each channel of the image around the nominal detection (0:
  // the nominal detection alone, its covariance Σc); stable iff detected in
  // at least min_detection_rate of them (thesis: 80 %).
  int monte_carlo_iterations = 100;
  double min_detection_rate = 0.80;

  // Per-pixel noise σ in levels; < 0: estimated (§5.4) from the image and
  // its auxiliary (robust σ of their aligned difference, with the aux as
  // noisy as the image when aux_equally_noisy, e.g. consecutive frames, or
  // noise-free otherwise, e.g. an average of frames), or from the image
  // alone (robust σ of its second differences) without one.
  double noise_sigma = -1.0;
  bool aux_equally_noisy = true;

  // Threads for the ROIs and Monte Carlo iterations (<= 0: all cores). The
  // result does not depend on it.
  int num_threads = 0;

  void Check() const;  // throws uw::Error naming the field
};

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

// The image with each stable spot's merged 68 % and 95 % ellipses
// (Mahalanobis radii 1.510 and 2.448), the iterations' centres faintly, and
// unstable or undetected lasers marked with their reason; below it a strip
// of 8x magnified crops around each spot, where sub-pixel ellipses are
// legible.
cv::Mat DrawSpotOverlay(const cv::Mat& image,
                        const std::vector<DetectedSpot>& spots);

}  // namespace uw
