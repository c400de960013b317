// One laser's region of interest (LSD step 1) and everything that the
// detection's steps and its Monte Carlo iterations share about it: the
// image patch, the beams, the aligned auxiliary patch, the backgrounds, the
// nominal fit.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "colmap_plugins/scene/model.h"
#include "laserscale/gaussian_spot_fit.h"
#include "laserscale/laser_setup.h"
#include "laserscale/spot_colour.h"
#include "laserscale/spot_detector_options.h"
#include "laserscale/spot_levels.h"

namespace uw::lsd {

// The background of a low-passed (texture-removed) ROI: its median per
// channel, and the level and spread of the increments' V above it, where
// the threshold starts. Increments rather than levels make V the laser's
// channel on its spot whatever colour the background has (underwater, a red
// laser's channel is the darkest).
struct Background {
  cv::Scalar levels = cv::Scalar::all(0.0);
  RobustLevel value;
};

// One laser's region of interest with everything the Monte Carlo
// iterations share (LSD steps 1-4, computed once).
struct Roi {
  std::string problem;  // non-empty: nothing to detect in it
  cv::Rect rect;
  // Every laser's beam image in ROI coordinates (this ROI's laser is
  // `laser`), and where the aux shows their spots, mapped into the ROI by
  // the alignment (empty without an aux).
  size_t laser = 0;
  std::vector<std::vector<Eigen::Vector2d>> beams;
  std::vector<std::vector<Eigen::Vector2d>> aux_beams;
  // The alignment, for AuxView (OpenCV pixel convention).
  Eigen::Matrix3d aux_view_from_roi = Eigen::Matrix3d::Identity();
  // The σ of the aligned aux's noise per unit σ of the aux's: bilinear
  // resampling averages neighbouring pixels.
  double aux_noise_gain = 1.0;
  LaserColour colour;
  cv::Mat main;   // CV_32FC3 levels of the image
  cv::Mat aux;    // CV_32FC3 aligned, matched aux; empty: none
  cv::Mat valid;  // CV_8U, 255 where the texture-removed value exists
  // Per channel, CV_8U 255 where the image (the aligned aux, before
  // matching) clips it or a pixel the low-pass mixes in does: there its
  // level is only a bound.
  std::array<cv::Mat, 3> clipped_main;
  std::array<cv::Mat, 3> clipped_aux;
  std::string texture_note;  // why the texture was not removed
  // Why the nominal detection found nothing though something bright lay on
  // the beam: it was not of the laser's colour.
  std::string colour_note;
  // With texture_note: the aux shows another scene, not just a noisy one
  // (its texture would have matched; AlignAux).
  bool aux_mismatch = false;
  // Of the nominal low-passed texture-removed image (of the image without
  // an aux), and of the aux's side of the difference (for its print).
  Background background;
  Background print_background;
  // The nominal detection's signal channel: the iterations fit the same.
  int channel = -1;
  // The aux's own spot ("shifted" lasers) after alignment: a print in the
  // difference, fitted with the spot where they overlap (amplitude > 0 in
  // aux - main).
  std::optional<GaussianSpot> print;
  cv::Mat print_window;  // CV_8U pixels of the print's fit
  // The nominal fit, where the Monte Carlo iterations start, and the print
  // as fitted with it (amplitude < 0 in main - aux), which stays fixed in
  // them: they perturb the image, not the aux.
  std::optional<GaussianSpot> nominal_spot;
  std::optional<GaussianSpot> nominal_print;
};

// Where the aligned aux shows what the aux has at ROI pixel p (both COLMAP
// convention, ROI coordinates).
Eigen::Vector2d AuxView(const Roi& roi, const Eigen::Vector2d& p);

// LSD step 1: the ROI of each laser of `setup`, in its order, with its
// image patch (`image`: 8-bit BGR); a laser whose beam does not project
// into the image gets a `problem` and no patch.
std::vector<Roi> PredictRois(const cv::Mat& image, const Camera& camera,
                             const LaserSetup& setup,
                             const SpotDetectorOptions& options);

// The part of `roi` inside `window` (ROI coordinates), for the Monte Carlo
// iterations: they need only the neighbourhood of the nominal detection.
Roi Crop(const Roi& roi, const cv::Rect& window);

}  // namespace uw::lsd
