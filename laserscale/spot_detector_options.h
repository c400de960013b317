// The options of the laser-spot detector (laserscale/spot_detector.h), one
// group per step of LSD (ch4 spec §5; docs/laserscale_detector.md), with
// their defaults and the rules between them.
#pragma once

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
  // A spot found where the aux shows another scene (it did not match
  // where its texture would have: AlignAux) is not used (not stable,
  // problem "not used: texture not removed ..."): with the texture left
  // in, a white shell or a highlight passes for the laser, and passes every
  // Monte Carlo iteration (seen on real frames without lasers: a shell,
  // rate 1.0, aux NCC 0.30). An aux merely too noisy to match keeps its
  // spots. false keeps them all.
  bool require_texture_removal = true;

  // 6. Gaussian low-pass against noise and compression artefacts.
  double lowpass_sigma_px = 1.0;

  // 7. HSV threshold on the increments over the ROI's median (per channel)
  // of the texture-removed image (of the image without an aux): V >= the
  // increments' median + value_threshold_sigmas robust σ (the nominal one
  // and the Monte Carlo noise in quadrature; and >= min_value levels). The
  // hue test (within hue_tolerance_deg of the laser colour's hue, red
  // wrapping at 0/360, for saturation >= min_saturation) is off by default:
  // a pixel's hue in encoded levels follows the background under it; the
  // colour test after the fit (below) judges the spot's colour as a whole.
  // On red lasers 30-40 deg and 0.3 reject pixels of other colours.
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

  // 11b. The colour test (docs/laserscale_detector.md): the fitted spot's
  // amplitude per channel in linear light (levels decoded with the sRGB
  // curve when srgb_levels, as cameras encode their files) must lie within
  // max_colour_angle_deg of the laser's colour (lasers.json; a laser's one
  // wavelength keeps its colour at any range), allowing
  // colour_noise_sigmas σ of its noise; else the spot is not detected. A
  // white shell, a highlight or a texture residue has the colour of the
  // lamp's light after the water: 50-85 deg from a red laser on uwsim,
  // true spots 0-20 deg, and up to ~60 deg for faint spots in JPEG, whose
  // chroma subsampling averages their colour away. 180 switches it off.
  double max_colour_angle_deg = 45.0;
  double colour_noise_sigmas = 2.0;
  bool srgb_levels = true;

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

}  // namespace uw
