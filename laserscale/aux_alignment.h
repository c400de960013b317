// LSD steps 2-4: the auxiliary image (the same scene with the lasers off or
// moved, e.g. the next frame) aligned on a laser's ROI, so that subtracting
// it removes the texture under the spot: FFT normalised cross-correlation
// for the translation, an ECC homography for the rest, histogram matching
// for the exposure.
#pragma once

#include <opencv2/core.hpp>

#include "laserscale/spot_detector_options.h"
#include "laserscale/spot_roi.h"

namespace uw::lsd {

// Maps `aux` (CV_32F, one channel) so that its histogram over `mask`
// matches that of `main` there: continuous CDF matching on 256 bins of one
// level each. Levels beyond the matched range (the spots, which the mask
// leaves out) continue it with slope 1, keeping their shape.
void MatchHistogram(const cv::Mat& main, const cv::Mat& mask, cv::Mat* aux);

// Replaces the pixels far above the patch's typical level (spots: a
// saturated spot is white in every channel), and a few pixels around them,
// by the median, so that the alignment follows the texture: in a "shifted"
// aux the spots move with the camera, not with the scene.
void FlattenHighlights(cv::Mat* patch);

// The NCC of `patch` (CV_32F, one channel) with another frame of the same
// scene and sensor: s² / (s² + n²), with n² the noise variance (from the
// median absolute second difference) and s² the patch's variance less it.
double SameSceneNcc(const cv::Mat& patch);

// LSD steps 2-4: the aux patch of the ROI, aligned on the laser's weakest
// channel (the spots, which move differently from the texture, barely pull
// it) and matched to the image's histograms. Sets roi->aux and roi->valid,
// or roi->texture_note when the aux cannot be trusted, and
// roi->aux_mismatch when it shows another scene (an NCC below
// min_alignment_ncc where SameSceneNcc is 0.75 or more).
// `image`, `aux`: 8-bit BGR of one size; `roi` from PredictRois.
void AlignAux(const cv::Mat& image, const cv::Mat& aux,
              const SpotDetectorOptions& options, Roi* roi);

}  // namespace uw::lsd
