// The detection of a spot in one ROI (LSD steps 5-11): the texture-removed,
// low-passed image, its threshold above the background, the component and
// the Gaussian fitted to it; once nominally (PrepareRoi, which also aligns
// the aux and finds the aux's print of the spot) and once per Monte Carlo
// iteration on a noisy copy of the ROI's image.
#pragma once

#include <optional>

#include <opencv2/core.hpp>

#include "laserscale/gaussian_spot_fit.h"
#include "laserscale/spot_detector_options.h"
#include "laserscale/spot_roi.h"

namespace uw::lsd {

// The low-passed texture-removed image of LSD steps 5-6: max(main - aux, 0)
// per channel (sign -1: max(aux - main, 0), where the aux's print shows),
// or `main` itself without an aux.
cv::Mat CleanImage(const Roi& roi, const cv::Mat& main, int sign,
                   const SpotDetectorOptions& options);

// The fit's signal: the low-passed signed difference in one channel (the
// aux's print negative), or that channel of `main` without an aux.
cv::Mat SignalImage(const Roi& roi, const cv::Mat& main, int sign, int channel,
                    const SpotDetectorOptions& options);

// The background of `clean` (CV_32FC3) under `valid`: its median per
// channel and the robust level of V above it.
Background MeasureBackground(const cv::Mat& clean, const cv::Mat& valid);

// What one run found.
struct RoiRun {
  GaussianSpot spot;
  int channel = 0;  // of the signal the spot was fitted on
  // Its fit window, and where it looked: the fit samples and the rival
  // components.
  cv::Mat window;
  cv::Rect extent;
  std::optional<GaussianSpot> print;  // fitted with the spot, if it was
};

// One run of LSD steps 5-11 on `main` (the ROI's image levels, with or
// without Monte Carlo noise): the fitted spot in ROI coordinates, or none.
// `sign` -1 finds the aux's print instead, with no beam constraint.
// `background` is the nominal one of this sign; `extra_sigma` the σ of the
// noise added to `main`, which raises the threshold as it raises the
// noise. `channel` is the signal's channel, < 0: the one in which the
// component is brightest (V's channel on the spot).
std::optional<RoiRun> DetectInRoi(const Roi& roi, const cv::Mat& main, int sign,
                                  const Background& background,
                                  double extra_sigma, int channel,
                                  const SpotDetectorOptions& options);

// The colour of a run's spot (the nominal one: the Monte Carlo
// iterations keep its verdict): per channel, the amplitude of its fitted
// shape over a constant, by least squares over the window's pixels that
// clip in neither frame and lie off the aux's print, in linear light over
// the aux's level at its peak (the fitted constant without an aux); its σ
// from the pixels' noise_sigma (levels, of the increment).
SpotRgb SpotColour(const Roi& roi, const RoiRun& run, double noise_sigma,
                   const SpotDetectorOptions& options);

// LSD steps 2-4, the nominal backgrounds of the thresholds, the aux's
// print and the nominal detection, refused (none, with the roi's
// colour_note) when its colour is not the laser's (IsLaserColour).
// Fills `roi` (from PredictRois) for the Monte Carlo iterations; `aux`
// may be empty.
std::optional<RoiRun> PrepareRoi(const cv::Mat& image, const cv::Mat& aux,
                                 const SpotDetectorOptions& options, Roi* roi);

}  // namespace uw::lsd
