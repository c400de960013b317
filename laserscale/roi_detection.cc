#include "laserscale/roi_detection.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

#include "laserscale/aux_alignment.h"
#include "laserscale/beam_image.h"
#include "laserscale/spot_levels.h"
#include "laserscale/spot_segmentation.h"

namespace uw::lsd {
namespace {

// Spots of another colour left out before giving up on a ROI.
constexpr int kColourRetries = 2;

}  // namespace

cv::Mat CleanImage(const Roi& roi, const cv::Mat& main, int sign,
                   const SpotDetectorOptions& options) {
  if (roi.aux.empty()) return LowPass(main, options.lowpass_sigma_px);
  cv::Mat clean;
  cv::max(sign > 0 ? cv::Mat(main - roi.aux) : cv::Mat(roi.aux - main), 0.0,
          clean);
  return LowPass(clean, options.lowpass_sigma_px);
}

cv::Mat SignalImage(const Roi& roi, const cv::Mat& main, int sign, int channel,
                    const SpotDetectorOptions& options) {
  cv::Mat signal = Channel(main, channel);
  if (!roi.aux.empty()) {
    signal = sign * (signal - Channel(roi.aux, channel));
  }
  return LowPass(signal, options.lowpass_sigma_px);
}

Background MeasureBackground(const cv::Mat& clean, const cv::Mat& valid) {
  Background background;
  for (int c = 0; c < 3; ++c) {
    background.levels[c] = RobustStats(Channel(clean, c), valid).median;
  }
  background.value = RobustStats(ValueImage(clean - background.levels), valid);
  return background;
}

SpotRgb SpotColour(const Roi& roi, const RoiRun& run, double noise_sigma,
                   const SpotDetectorOptions& options) {
  // The raw spot's shape: the fitted one is that of the low-passed image.
  const auto precision = [&](const Eigen::Matrix2d& fitted) {
    const Eigen::Matrix2d raw =
        fitted - Square(options.lowpass_sigma_px) * Eigen::Matrix2d::Identity();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> shape(raw);
    return shape.eigenvalues()(0) > 0.1 ? Eigen::Matrix2d(raw.inverse())
                                        : Eigen::Matrix2d(fitted.inverse());
  };
  const Eigen::Matrix2d spot_precision = precision(run.spot.covariance);
  // The fitted channel's peak, from the censored fit (which a clipped top
  // does not hide), for the raw shape: the low-pass keeps the volume.
  const double fitted_peak =
      run.spot.amplitude * std::sqrt(run.spot.covariance.determinant() *
                                     spot_precision.determinant());
  const Eigen::Matrix2d print_precision =
      run.print ? precision(run.print->covariance) : Eigen::Matrix2d::Zero();
  const cv::Point peak(
      std::clamp(static_cast<int>(std::floor(run.spot.mean.x())), 0,
                 roi.main.cols - 1),
      std::clamp(static_cast<int>(std::floor(run.spot.mean.y())), 0,
                 roi.main.rows - 1));
  SpotRgb colour;
  for (int c = 0; c < 3; ++c) {
    // Least squares of the channel's increment on the spot's shape and a
    // constant, over the window's pixels that clip in neither frame (a
    // clipped channel's amplitude comes from its tails) and lie off the
    // aux's print.
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    int count = 0;
    bool clipped = false;
    double shape_squared = 0.0;  // of every pixel of the window
    for (int r = 0; r < run.window.rows; ++r) {
      for (int col = 0; col < run.window.cols; ++col) {
        if (!run.window.at<uint8_t>(r, col)) continue;
        const Eigen::Vector2d x(col + 0.5, r + 0.5);
        const Eigen::Vector2d d = x - run.spot.mean;
        const double shape = std::exp(-0.5 * d.dot(spot_precision * d));
        shape_squared += shape * shape;
        const double main = roi.main.at<cv::Vec3f>(r, col)[c];
        const double aux =
            roi.aux.empty() ? 0.0 : roi.aux.at<cv::Vec3f>(r, col)[c];
        if (main >= options.saturation_level ||
            (!roi.aux.empty() && roi.clipped_aux[c].at<uint8_t>(r, col))) {
          clipped = true;
          continue;
        }
        if (run.print) {
          const Eigen::Vector2d e = x - run.print->mean;
          if (e.dot(print_precision * e) < 9.0) continue;
        }
        // With an aux the difference has no background to fit.
        const Eigen::Vector2d row(roi.aux.empty() ? 1.0 : 0.0, shape);
        normal += row * row.transpose();
        rhs += row * (main - aux);
        ++count;
      }
    }
    // Too few pixels, or too little of the spot's shape among them, for
    // a fit: the amplitude is the clip's bound if the channel clips there,
    // else nothing was seen.
    if (!roi.aux.empty()) normal(0, 0) = 1.0;
    const bool solvable =
        count >= 5 && normal.determinant() > 1e-6 * Square(normal.trace());
    const Eigen::Matrix2d inverse =
        solvable ? Eigen::Matrix2d(normal.inverse()) : Eigen::Matrix2d::Zero();
    const Eigen::Vector2d fit = inverse * rhs;
    // In linear light at the peak, over what lies under it: the aux there,
    // or the fitted constant (the ROI's level) without one.
    const double base = !roi.aux.empty() ? roi.aux.at<cv::Vec3f>(peak)[c]
                        : solvable       ? fit(0)
                                         : roi.background.levels[c];
    double amplitude = fit(1);
    double amplitude_sigma = noise_sigma * std::sqrt(inverse(1, 1));
    if (c == run.channel && (clipped || !solvable)) {
      // Its top clipped: the censored fit's peak.
      amplitude = fitted_peak;
      amplitude_sigma = noise_sigma / std::sqrt(std::max(shape_squared, 1.0));
    } else if (!solvable && clipped) {
      amplitude = options.saturation_level - base;
      amplitude_sigma = 0.0;
    } else if (!solvable) {
      colour.measured = false;
      continue;
    }
    const int rgb = 2 - c;
    colour.rgb(rgb) = LinearLevel(base + amplitude, options.srgb_levels) -
                      LinearLevel(base, options.srgb_levels);
    colour.sigma(rgb) =
        amplitude_sigma *
        (LinearLevel(base + amplitude + 0.5, options.srgb_levels) -
         LinearLevel(base + amplitude - 0.5, options.srgb_levels));
  }
  return colour;
}

std::optional<RoiRun> DetectInRoi(const Roi& roi, const cv::Mat& main, int sign,
                                  const Background& background,
                                  double extra_sigma, int channel,
                                  const SpotDetectorOptions& options) {
  const cv::Mat clean =
      CleanImage(roi, main, sign, options) - background.levels;
  // 7-8. Threshold above the background by the noise of this run: the
  // nominal robust σ and the low-passed added noise, in quadrature.
  const double sigma = std::hypot(background.value.sigma,
                                  extra_sigma * LowPassNoiseGain(options));
  // Capped where clipping starts: a clipped pixel is as bright as the image
  // can tell.
  const double clip = options.saturation_level -
                      std::max({background.levels[0], background.levels[1],
                                background.levels[2]});
  const double min_value = std::max(
      options.min_value,
      std::min(background.value.median + options.value_threshold_sigmas * sigma,
               clip));
  const cv::Mat mask =
      ColourMask(clean, roi.valid, roi.colour, min_value, options);

  // 9. The component.
  cv::Rect rivals;
  const cv::Mat component =
      BestComponent(mask, clean, sign > 0 ? roi.beams : roi.aux_beams,
                    roi.laser, options, &rivals);
  if (component.empty()) return std::nullopt;
  RoiRun run;
  run.channel = channel;
  if (run.channel < 0) {
    cv::Scalar sums = cv::Scalar::all(0.0);
    for (int r = 0; r < clean.rows; ++r) {
      const uint8_t* in = component.ptr<uint8_t>(r);
      const cv::Vec3f* row = clean.ptr<cv::Vec3f>(r);
      for (int c = 0; c < clean.cols; ++c) {
        if (!in[c]) continue;
        for (int k = 0; k < 3; ++k) sums[k] += row[c][k];
      }
    }
    run.channel =
        static_cast<int>(std::max_element(&sums[0], &sums[0] + 3) - &sums[0]);
  }
  const cv::Mat signal = SignalImage(roi, main, sign, run.channel, options);

  // 10-11. Fit window: the component and its surroundings.
  const int grow = 2 * options.fit_margin_px + 1;
  cv::dilate(
      component, run.window,
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(grow, grow)));
  cv::bitwise_and(run.window, roi.valid, run.window);
  const cv::Mat& clipped_plus =
      (sign > 0 ? roi.clipped_main : roi.clipped_aux)[run.channel];
  const cv::Mat& clipped_minus =
      (sign > 0 ? roi.clipped_aux : roi.clipped_main)[run.channel];
  FitSamples samples;
  AddSamples(run.window, signal, clipped_plus, clipped_minus, &samples);
  const std::vector<double>& ys = samples.ys;
  if (ys.size() < 7) return std::nullopt;

  // The start: background (a low quantile of the window), and the nominal
  // fit or else the peak and intensity moments over the window.
  std::vector<double> sorted = ys;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 4,
                   sorted.end());
  const double start_background = sorted[sorted.size() / 4];
  GaussianSpot start;
  if (roi.nominal_spot) {
    start = *roi.nominal_spot;
  } else {
    double weight = 0.0;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (size_t i = 0; i < ys.size(); ++i) {
      const double w = std::max(ys[i] - start_background, 0.0);
      weight += w;
      mean += w * samples.xs[i];
      start.amplitude = std::max(start.amplitude, w);
    }
    if (!(weight > 0.0)) return std::nullopt;
    mean /= weight;
    Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
    for (size_t i = 0; i < ys.size(); ++i) {
      const Eigen::Vector2d d = samples.xs[i] - mean;
      second += std::max(ys[i] - start_background, 0.0) * d * d.transpose();
    }
    start.mean = mean;
    start.covariance = second / weight + 0.25 * Eigen::Matrix2d::Identity();
  }

  run.extent = rivals | cv::boundingRect(run.window);
  if (sign > 0 && roi.nominal_print) {
    const GaussianSpot& print = *roi.nominal_print;
    const Eigen::Matrix2d precision = print.covariance.inverse();
    for (size_t i = 0; i < ys.size(); ++i) {
      const Eigen::Vector2d d = samples.xs[i] - print.mean;
      samples.ys[i] -= print.amplitude * std::exp(-0.5 * d.dot(precision * d));
    }
  } else if (sign > 0 && roi.print) {
    // The aux's print joins the fit where it reaches the window, with its
    // own samples, so that its shape is determined.
    const Eigen::Matrix2d print_precision = roi.print->covariance.inverse();
    for (const Eigen::Vector2d& x : samples.xs) {
      const Eigen::Vector2d d = x - roi.print->mean;
      if (d.dot(print_precision * d) <= 9.0) {
        run.print = *roi.print;
        run.print->amplitude = -run.print->amplitude;  // in main - aux
        break;
      }
    }
    if (run.print) {
      cv::Mat print_only;
      cv::bitwise_and(roi.print_window, ~run.window, print_only);
      AddSamples(print_only, signal, clipped_plus, clipped_minus, &samples);
      run.extent |= cv::boundingRect(roi.print_window);
    }
  }
  PrintGeometry geometry;
  if (run.print) {
    geometry.offset = AuxView(roi, start.mean) - start.mean;
    geometry.along = DirectionNear(roi.beams[roi.laser], start.mean);
  }
  if (!FitSpot(samples, start_background, start, geometry, &run.spot,
               run.print ? &*run.print : nullptr)) {
    return std::nullopt;
  }

  // A fit that left the window, turned negative or degenerate is no spot.
  const GaussianSpot& spot = run.spot;
  const cv::Rect box = cv::boundingRect(run.window);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> shape(spot.covariance);
  // A Gaussian wider than the window it was fitted on is not determined.
  const double max_extent =
      Square(static_cast<double>(std::max(box.width, box.height)));
  if (!(spot.amplitude > 0.0) || !spot.mean.allFinite() ||
      !(shape.eigenvalues()(0) >= 0.01) ||
      !(shape.eigenvalues()(1) <= max_extent) || spot.mean.x() < box.x ||
      spot.mean.x() > box.x + box.width || spot.mean.y() < box.y ||
      spot.mean.y() > box.y + box.height) {
    return std::nullopt;
  }
  return run;
}

std::optional<RoiRun> PrepareRoi(const cv::Mat& image, const cv::Mat& aux,
                                 const SpotDetectorOptions& options, Roi* roi) {
  if (options.texture_removal && !aux.empty()) {
    AlignAux(image, aux, options, roi);
  }
  for (int c = 0; c < 3; ++c) {
    roi->clipped_main[c] = Clipped(roi->main, c, options);
  }
  roi->background =
      MeasureBackground(CleanImage(*roi, roi->main, 1, options), roi->valid);
  if (!roi->aux.empty()) {
    roi->print_background =
        MeasureBackground(CleanImage(*roi, roi->main, -1, options), roi->valid);
    const std::optional<RoiRun> print = DetectInRoi(
        *roi, roi->main, -1, roi->print_background, 0.0, -1, options);
    if (print) {
      roi->print = print->spot;
      roi->print_window = print->window;
    }
  }
  std::optional<RoiRun> nominal =
      DetectInRoi(*roi, roi->main, 1, roi->background, 0.0, -1, options);
  if (options.max_colour_angle_deg < 180.0) {
    // The image's noise (options' or the robust σ of the ROI's second
    // differences, at least 8-bit quantisation's), and the aux's in the
    // difference.
    double noise_sigma = options.noise_sigma;
    if (noise_sigma < 0.0) {
      std::vector<float> values;
      AppendSecondDifferences(roi->main, &values);
      noise_sigma =
          std::max(SecondDifferenceSigma(&values), 1.0 / std::sqrt(12.0));
    }
    if (!roi->aux.empty() && options.aux_equally_noisy) {
      noise_sigma *= std::hypot(1.0, roi->aux_noise_gain);
    }
    // A spot not of the laser's colour is left out (with its
    // surroundings, for the Monte Carlo too) and the next brightest tried:
    // a shell on the beam must not hide the laser's spot further along.
    for (int attempt = 0; nominal; ++attempt) {
      const SpotRgb colour = SpotColour(*roi, *nominal, noise_sigma, options);
      double angle_deg = 0.0;
      if (IsLaserColour(colour, roi->colour.rgb, options, &angle_deg)) break;
      if (roi->colour_note.empty()) {
        roi->colour_note = fmt::format(
            "a bright spot on the beam at ({:.1f}, {:.1f}) is not the "
            "laser's colour: {:.0f} deg from it (linear RGB {:.3g}, {:.3g}, "
            "{:.3g})",
            nominal->spot.mean.x() + roi->rect.x,
            nominal->spot.mean.y() + roi->rect.y, angle_deg, colour.rgb(0),
            colour.rgb(1), colour.rgb(2));
      }
      if (attempt == kColourRetries) return std::nullopt;
      roi->valid.setTo(0, nominal->window);
      nominal =
          DetectInRoi(*roi, roi->main, 1, roi->background, 0.0, -1, options);
    }
  }
  if (nominal) {
    roi->channel = nominal->channel;
    roi->nominal_spot = nominal->spot;
    roi->nominal_print = nominal->print;
  }
  return nominal;
}

}  // namespace uw::lsd
