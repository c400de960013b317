#include "laserscale/spot_detector.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "colmap_plugins/cameras/camera_models.h"
#include "common/util/error.h"
#include "common/util/random.h"

namespace uw {
namespace {

// Mahalanobis radii of the 68 % and 95 % ellipses of a 2D Gaussian,
// sqrt(-2 ln(1 - p)).
constexpr double kRadius68 = 1.5096;
constexpr double kRadius95 = 2.4477;
// MAD of a Gaussian = 0.6745 σ.
constexpr double kMadToSigma = 1.4826;
// Points along each beam for its image (distortion bends it).
constexpr int kBeamSamples = 64;

double Square(double x) { return x * x; }

// HSV hue (degrees in [0, 360)) of an RGB triple, hexcone definition.
double HueDeg(double r, double g, double b) {
  const double max = std::max({r, g, b});
  const double chroma = max - std::min({r, g, b});
  if (chroma <= 0.0) return 0.0;
  if (max == r) return 60.0 * std::fmod((g - b) / chroma + 6.0, 6.0);
  if (max == g) return 60.0 * ((b - r) / chroma + 2.0);
  return 60.0 * ((r - g) / chroma + 4.0);
}

double HueDistanceDeg(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

// What the detector needs of a laser's colour, in OpenCV's BGR channel
// order.
struct LaserColour {
  double hue_deg = 0.0;
  bool chromatic = true;  // false: white (saturation < 0.1), no hue test
  int dominant = 2;       // its strongest channel: V on its pixels
  int weakest = 0;        // its weakest: the least disturbed by the spots
};

LaserColour ColourOf(const Laser& laser) {
  const Eigen::Vector3d& rgb = laser.colour;
  LaserColour colour;
  colour.hue_deg = HueDeg(rgb(0), rgb(1), rgb(2));
  colour.chromatic = rgb.maxCoeff() > 0.0 &&
                     (rgb.maxCoeff() - rgb.minCoeff()) / rgb.maxCoeff() >= 0.1;
  int max_rgb = 0;
  int min_rgb = 0;
  rgb.maxCoeff(&max_rgb);
  rgb.minCoeff(&min_rgb);
  colour.dominant = 2 - max_rgb;
  colour.weakest = 2 - min_rgb;
  return colour;
}

// An elliptical Gaussian amplitude * exp(-1/2 (x - mean)^T cov^-1 (x - mean))
// in ROI pixel coordinates (COLMAP convention, origin at the ROI's corner).
struct GaussianSpot {
  double amplitude = 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
};

// A background level and the robust σ around it.
struct RobustLevel {
  double median = 0.0;
  double sigma = 0.0;
};

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
Eigen::Vector2d AuxView(const Roi& roi, const Eigen::Vector2d& p) {
  const Eigen::Vector3d h =
      roi.aux_view_from_roi * Eigen::Vector3d(p.x() - 0.5, p.y() - 0.5, 1.0);
  return h.head<2>() / h.z() + Eigen::Vector2d(0.5, 0.5);
}

// The unit direction of the polyline at its point nearest to p.
Eigen::Vector2d DirectionNear(const std::vector<Eigen::Vector2d>& line,
                              const Eigen::Vector2d& p) {
  Eigen::Vector2d best = Eigen::Vector2d::UnitX();
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d d = line[i] - line[i - 1];
    if (d.squaredNorm() == 0.0) continue;
    const double t =
        std::clamp((p - line[i - 1]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double distance = (p - (line[i - 1] + t * d)).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best = d.normalized();
    }
  }
  return best;
}

struct Detection {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // image coordinates
  Eigen::Matrix2d centre_cov = Eigen::Matrix2d::Zero();
};

// Distance from p to the polyline.
double DistanceToPolyline(const Eigen::Vector2d& p,
                          const std::vector<Eigen::Vector2d>& line) {
  double best = std::numeric_limits<double>::infinity();
  if (line.size() == 1) return (p - line[0]).norm();
  for (size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d d = line[i] - line[i - 1];
    const double length2 = d.squaredNorm();
    const double t =
        length2 > 0.0 ? std::clamp((p - line[i - 1]).dot(d) / length2, 0.0, 1.0)
                      : 0.0;
    best = std::min(best, (p - (line[i - 1] + t * d)).norm());
  }
  return best;
}

// The beam's points at camera depths [min_range_m, max_range_m] that the
// camera model projects and unprojects consistently (a distortion that
// folds back would put them elsewhere).
std::vector<Eigen::Vector2d> BeamImage(const Camera& camera, const Laser& laser,
                                       const SpotDetectorOptions& options) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= kBeamSamples; ++i) {
    const double z =
        options.min_range_m +
        (options.max_range_m - options.min_range_m) * i / kBeamSamples;
    const Eigen::Vector3d point_in_cam =
        laser.origin_in_cam + (z - laser.origin_in_cam.z()) /
                                  laser.direction_in_cam.z() *
                                  laser.direction_in_cam;
    const Eigen::Vector2d pixel = CameraModelImgFromCam(
        camera.model_id, camera.params.data(), point_in_cam);
    if (!pixel.allFinite()) continue;
    const Eigen::Vector3d ray =
        CameraModelCamFromImg(camera.model_id, camera.params.data(), pixel);
    if ((ray.head<2>() - point_in_cam.head<2>() / point_in_cam.z()).norm() >
        1e-6) {
      continue;
    }
    points.push_back(pixel);
  }
  return points;
}

// Median and MAD-based σ of the values of `image` (CV_32F) under `mask`,
// from a regular subsample of about kRobustSamples pixels: plenty for a
// level and a spread, and a fraction of the cost on large patches.
constexpr size_t kRobustSamples = 4096;
RobustLevel RobustStats(const cv::Mat& image, const cv::Mat& mask) {
  const size_t stride = std::max<size_t>(1, image.total() / kRobustSamples);
  std::vector<float> values;
  values.reserve(image.total() / stride + 1);
  size_t index = 0;
  for (int r = 0; r < image.rows; ++r) {
    const float* row = image.ptr<float>(r);
    const uint8_t* m = mask.ptr<uint8_t>(r);
    for (int c = 0; c < image.cols; ++c, ++index) {
      if (index % stride == 0 && m[c]) values.push_back(row[c]);
    }
  }
  if (values.empty()) return {};
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  const double median = *middle;
  for (float& v : values) v = std::abs(v - static_cast<float>(median));
  std::nth_element(values.begin(), middle, values.end());
  return {median, kMadToSigma * *middle};
}

cv::Mat Channel(const cv::Mat& image, int channel) {
  cv::Mat out;
  cv::extractChannel(image, out, channel);
  return out;
}

// The σ of white noise after LowPass, per unit σ before: the L2 norm of the
// (separable) kernel.
double LowPassNoiseGain(const SpotDetectorOptions& options) {
  if (options.lowpass_sigma_px <= 0.0) return 1.0;
  // GaussianBlur's kernel size for float images.
  const cv::Mat kernel =
      cv::getGaussianKernel(cvRound(options.lowpass_sigma_px * 8.0 + 1.0) | 1,
                            options.lowpass_sigma_px, CV_64F);
  return Square(cv::norm(kernel));
}

cv::Mat LowPass(const cv::Mat& image, double sigma) {
  if (sigma <= 0.0) return image;
  cv::Mat out;
  cv::GaussianBlur(image, out, cv::Size(0, 0), sigma, sigma,
                   cv::BORDER_REPLICATE);
  return out;
}

// Maps `aux` (CV_32F, one channel) so that its histogram over `mask`
// matches that of `main` there: continuous CDF matching on 256 bins of one
// level each. Levels beyond the matched range (the spots, which the mask
// leaves out) continue it with slope 1, keeping their shape.
void MatchHistogram(const cv::Mat& main, const cv::Mat& mask, cv::Mat* aux) {
  constexpr int kBins = 256;
  // cdf[k]: the pixels below level k - 0.5, the lower edge of bin k.
  std::array<double, kBins + 1> cdf_main{};
  std::array<double, kBins + 1> cdf_aux{};
  const auto bin = [](float v) {
    return std::clamp(static_cast<int>(std::lround(v)), 0, kBins - 1);
  };
  for (int r = 0; r < main.rows; ++r) {
    for (int c = 0; c < main.cols; ++c) {
      if (!mask.at<uint8_t>(r, c)) continue;
      cdf_main[bin(main.at<float>(r, c)) + 1] += 1.0;
      cdf_aux[bin(aux->at<float>(r, c)) + 1] += 1.0;
    }
  }
  for (int k = 1; k <= kBins; ++k) {
    cdf_main[k] += cdf_main[k - 1];
    cdf_aux[k] += cdf_aux[k - 1];
  }
  const double total = cdf_main[kBins];
  if (total < 1.0) return;
  // The occupied range of a histogram, from the lower edge of its first
  // bin to the upper edge of its last.
  const auto range = [&](const std::array<double, kBins + 1>& cdf) {
    int low = 0;
    while (cdf[low + 1] == 0.0) ++low;
    int high = kBins - 1;
    while (cdf[high] == total) --high;
    return std::pair(low - 0.5, high + 0.5);
  };
  const auto [aux_low, aux_high] = range(cdf_aux);
  const auto [main_low, main_high] = range(cdf_main);
  // The CDF is linear within a bin.
  const auto aux_cdf = [&](double level) {
    const double x = level + 0.5;
    const int k = std::min(static_cast<int>(x), kBins - 1);
    return cdf_aux[k] + (x - k) * (cdf_aux[k + 1] - cdf_aux[k]);
  };
  const auto main_inverse = [&](double p) {
    const int k = static_cast<int>(
        std::upper_bound(cdf_main.begin() + 1, cdf_main.end(), p) -
        cdf_main.begin());
    if (k > kBins) return main_high;
    return (k - 1) - 0.5 +
           (p - cdf_main[k - 1]) / (cdf_main[k] - cdf_main[k - 1]);
  };
  const auto map = [&](double v) {
    return v >= aux_high  ? main_high + (v - aux_high)
           : v <= aux_low ? main_low + (v - aux_low)
                          : main_inverse(aux_cdf(v));
  };
  // The map is piecewise linear with knots at bin edges: tabulated at
  // 1/kSteps levels and interpolated, it is exact to ~1e-3 levels. The
  // aligned aux lies in [0, 255] (bilinear samples of 8-bit levels).
  constexpr int kSteps = 8;
  std::array<float, 255 * kSteps + 2> table;
  for (size_t i = 0; i < table.size(); ++i) {
    table[i] = static_cast<float>(map(static_cast<double>(i) / kSteps));
  }
  for (int r = 0; r < aux->rows; ++r) {
    float* row = aux->ptr<float>(r);
    for (int c = 0; c < aux->cols; ++c) {
      const float x = std::clamp(row[c], 0.0f, 255.0f) * kSteps;
      const int i = static_cast<int>(x);
      row[c] = table[i] + (x - i) * (table[i + 1] - table[i]);
    }
  }
}

// Where channel c of `levels` (CV_32FC3) is clipped, grown by the
// low-pass's reach: CV_8U, 255 there.
cv::Mat Clipped(const cv::Mat& levels, int c,
                const SpotDetectorOptions& options) {
  const int reach = static_cast<int>(std::ceil(3.0 * options.lowpass_sigma_px));
  cv::Mat mask;
  cv::compare(Channel(levels, c), options.saturation_level, mask, cv::CMP_GE);
  cv::dilate(mask, mask,
             cv::getStructuringElement(cv::MORPH_ELLIPSE,
                                       cv::Size(2 * reach + 1, 2 * reach + 1)));
  return mask;
}

// Replaces the pixels far above the patch's typical level (spots: a
// saturated spot is white in every channel), and a few pixels around them,
// by the median, so that the alignment follows the texture: in a "shifted"
// aux the spots move with the camera, not with the scene.
void FlattenHighlights(cv::Mat* patch) {
  const RobustLevel level =
      RobustStats(*patch, cv::Mat(patch->size(), CV_8U, cv::Scalar(255)));
  cv::Mat high;
  cv::compare(*patch, level.median + 4.0 * std::max(level.sigma, 1.0), high,
              cv::CMP_GT);
  cv::dilate(high, high,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7)));
  patch->setTo(level.median, high);
}

// LSD steps 2-4: the aux patch of the ROI, aligned on the laser's weakest
// channel (the spots, which move differently from the texture, barely pull
// it) and matched to the image's histograms. Sets roi->aux and roi->valid,
// or roi->texture_note when the aux cannot be trusted.
void AlignAux(const cv::Mat& image, const cv::Mat& aux,
              const SpotDetectorOptions& options, Roi* roi) {
  const cv::Rect image_rect(0, 0, image.cols, image.rows);
  const cv::Rect search =
      cv::Rect(roi->rect.x - options.aux_search_px,
               roi->rect.y - options.aux_search_px,
               roi->rect.width + 2 * options.aux_search_px,
               roi->rect.height + 2 * options.aux_search_px) &
      image_rect;
  cv::Mat templ;
  cv::Mat input;
  Channel(image(roi->rect), roi->colour.weakest).convertTo(templ, CV_32F);
  Channel(aux(search), roi->colour.weakest).convertTo(input, CV_32F);
  FlattenHighlights(&templ);
  FlattenHighlights(&input);
  // OpenCV correlates in the Fourier domain and normalises with integral
  // images (Lewis's fast normalised cross-correlation).
  cv::Mat ncc;
  cv::matchTemplate(input, templ, ncc, cv::TM_CCOEFF_NORMED);
  double best = 0.0;
  cv::Point at;
  cv::minMaxLoc(ncc, nullptr, &best, nullptr, &at);
  if (!std::isfinite(best) || best < options.min_alignment_ncc) {
    char note[128];
    std::snprintf(note, sizeof(note),
                  "texture not removed: the aux does not match (NCC %.2f)",
                  std::isfinite(best) ? best : 0.0);
    roi->texture_note = note;
    return;
  }
  // ECC's warp maps template (ROI) coordinates to input (search) ones.
  const cv::Mat translation =
      (cv::Mat_<float>(3, 3) << 1, 0, at.x, 0, 1, at.y, 0, 0, 1);
  cv::Mat warp = translation.clone();
  try {
    cv::findTransformECC(
        templ, input, warp, cv::MOTION_HOMOGRAPHY,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                         options.ecc_iterations, 1e-4),
        cv::noArray(), 5);
  } catch (const cv::Exception&) {
    // ECC fails on nearly uniform patches; the NCC translation stands.
    warp = translation.clone();
  }
  // A homography that moves the ROI's corners farther than the search
  // allows is a divergence, not the camera's motion.
  const std::vector<cv::Point2f> corners = {
      {0.0f, 0.0f},
      {static_cast<float>(templ.cols), 0.0f},
      {0.0f, static_cast<float>(templ.rows)},
      {static_cast<float>(templ.cols), static_cast<float>(templ.rows)}};
  std::vector<cv::Point2f> moved;
  cv::perspectiveTransform(corners, moved, warp);
  for (size_t i = 0; i < corners.size(); ++i) {
    const cv::Point2f shift = moved[i] - corners[i] - cv::Point2f(at);
    if (!(std::hypot(shift.x, shift.y) <= options.aux_search_px)) {
      warp = translation.clone();
      break;
    }
  }
  // Where the aligned aux shows what the aux has at a pixel of the ROI
  // (OpenCV's convention, pixel centres at integers): the aux's pixel is
  // in the search region at the ROI's offset, and the warp takes the ROI
  // into the search region.
  Eigen::Matrix3d same_pixel = Eigen::Matrix3d::Identity();
  same_pixel.topRightCorner<2, 1>() =
      Eigen::Vector2d(roi->rect.x - search.x, roi->rect.y - search.y);
  Eigen::Matrix3d search_from_roi;
  cv::Mat warp_double;
  warp.convertTo(warp_double, CV_64F);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      search_from_roi(r, c) = warp_double.at<double>(r, c);
    }
  }
  roi->aux_view_from_roi = search_from_roi.inverse() * same_pixel;
  // Bilinear weights (1 - u, u) x (1 - v, v) at the ROI's centre, where the
  // sampling offset is that of the whole ROI up to the homography's slight
  // non-translation.
  const Eigen::Vector3d sampled =
      search_from_roi *
      Eigen::Vector3d(0.5 * (templ.cols - 1), 0.5 * (templ.rows - 1), 1.0);
  const Eigen::Vector2d offset = sampled.head<2>() / sampled.z();
  const double u = offset.x() - std::floor(offset.x());
  const double v = offset.y() - std::floor(offset.y());
  roi->aux_noise_gain =
      std::sqrt((Square(u) + Square(1.0 - u)) * (Square(v) + Square(1.0 - v)));
  // The aux's spots lie on the beams in the aux's own pixels.
  for (const std::vector<Eigen::Vector2d>& beam : roi->beams) {
    roi->aux_beams.emplace_back();
    for (const Eigen::Vector2d& p : beam) {
      roi->aux_beams.back().push_back(AuxView(*roi, p));
    }
  }
  cv::Mat aux_float;
  aux(search).convertTo(aux_float, CV_32FC3);
  cv::warpPerspective(aux_float, roi->aux, warp, templ.size(),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                      cv::BORDER_CONSTANT, cv::Scalar::all(0));
  const cv::Mat inside(input.size(), CV_8U, cv::Scalar(255));
  cv::warpPerspective(inside, roi->valid, warp, templ.size(),
                      cv::INTER_NEAREST | cv::WARP_INVERSE_MAP,
                      cv::BORDER_CONSTANT, cv::Scalar(0));
  // Bilinear samples on the warped border mix in the zero border.
  cv::erode(roi->valid, roi->valid, cv::Mat(), cv::Point(-1, -1), 1,
            cv::BORDER_CONSTANT, cv::Scalar(0));

  for (int c = 0; c < 3; ++c) {
    roi->clipped_aux[c] = Clipped(roi->aux, c, options);
  }

  // Histogram matching ignores the pixels the spots change (either frame's:
  // a difference far out in any channel), so that the spot's levels are not
  // mapped onto the aux's brightest texture.
  cv::Mat changed(templ.size(), CV_8U, cv::Scalar(0));
  for (int c = 0; c < 3; ++c) {
    const cv::Mat difference = Channel(roi->main, c) - Channel(roi->aux, c);
    const RobustLevel level = RobustStats(difference, roi->valid);
    const cv::Mat deviation = cv::abs(difference - level.median);
    cv::Mat far_out;
    cv::compare(deviation, 4.0 * std::max(level.sigma, 1.0), far_out,
                cv::CMP_GT);
    changed |= far_out;
  }
  cv::dilate(changed, changed,
             cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(5, 5)));
  cv::Mat histogram_mask;
  cv::bitwise_and(roi->valid, ~changed, histogram_mask);
  std::vector<cv::Mat> main_channels;
  std::vector<cv::Mat> aux_channels;
  cv::split(roi->main, main_channels);
  cv::split(roi->aux, aux_channels);
  for (int c = 0; c < 3; ++c) {
    MatchHistogram(main_channels[c], histogram_mask, &aux_channels[c]);
  }
  cv::merge(aux_channels, roi->aux);
}

// The opened colour mask of LSD step 7-8: pixels of the low-passed
// `clean` image (CV_32FC3) of the laser's hue, saturated enough and at
// least `min_value` bright.
cv::Mat ColourMask(const cv::Mat& clean, const cv::Mat& valid,
                   const LaserColour& colour, double min_value,
                   const SpotDetectorOptions& options) {
  cv::Mat mask(clean.size(), CV_8U, cv::Scalar(0));
  for (int r = 0; r < clean.rows; ++r) {
    const cv::Vec3f* row = clean.ptr<cv::Vec3f>(r);
    const uint8_t* ok = valid.ptr<uint8_t>(r);
    uint8_t* out = mask.ptr<uint8_t>(r);
    for (int c = 0; c < clean.cols; ++c) {
      if (!ok[c]) continue;
      const cv::Vec3f& bgr = row[c];
      const double value = std::max({bgr[0], bgr[1], bgr[2]});
      if (!(value >= min_value && value > 0.0)) continue;
      if (colour.chromatic) {
        const double saturation =
            (value - std::min({bgr[0], bgr[1], bgr[2]})) / value;
        if (saturation < options.min_saturation) continue;
        if (HueDistanceDeg(HueDeg(bgr[2], bgr[1], bgr[0]), colour.hue_deg) >
            options.hue_tolerance_deg) {
          continue;
        }
      }
      out[c] = 255;
    }
  }
  if (options.opening_radius_px > 0) {
    const int size = 2 * options.opening_radius_px + 1;
    cv::morphologyEx(
        mask, mask, cv::MORPH_OPEN,
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
  }
  return mask;
}

// Whether `p` may be laser `own`'s spot: within max_distance of its beam
// and no closer to another's (where the beams converge, a neighbour's spot
// can lie within the margin).
bool OnOwnBeam(const Eigen::Vector2d& p,
               const std::vector<std::vector<Eigen::Vector2d>>& beams,
               size_t own, double max_distance) {
  const double distance = DistanceToPolyline(p, beams[own]);
  if (distance > max_distance) return false;
  for (size_t l = 0; l < beams.size(); ++l) {
    if (l != own && !beams[l].empty() &&
        DistanceToPolyline(p, beams[l]) < distance) {
      return false;
    }
  }
  return true;
}

// LSD step 9: the component of `mask` with the largest summed V (of
// `clean`) whose centroid lies on beam `own` of `beams` (OnOwnBeam).
// Returns its mask, empty if there is none. `rivals` receives the bounding
// box of it and of the candidates whose summed V is at least
// kRivalFraction of its: those that noise could make win.
constexpr double kRivalFraction = 0.25;
cv::Mat BestComponent(const cv::Mat& mask, const cv::Mat& clean,
                      const std::vector<std::vector<Eigen::Vector2d>>& beams,
                      size_t own, const SpotDetectorOptions& options,
                      cv::Rect* rivals) {
  cv::Mat labels;
  cv::Mat stats;
  cv::Mat centroids;
  const int count =
      cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8);
  if (count <= 1) return {};
  std::vector<double> summed_value(count, 0.0);
  for (int r = 0; r < labels.rows; ++r) {
    const int* label = labels.ptr<int>(r);
    const cv::Vec3f* row = clean.ptr<cv::Vec3f>(r);
    for (int c = 0; c < labels.cols; ++c) {
      if (label[c] > 0) {
        summed_value[label[c]] += std::max({row[c][0], row[c][1], row[c][2]});
      }
    }
  }
  std::vector<int> candidates;
  int best = 0;
  for (int k = 1; k < count; ++k) {
    const int area = stats.at<int>(k, cv::CC_STAT_AREA);
    if (area < options.min_area_px || area > options.max_area_px) continue;
    // Pixel centres are at +0.5 in the COLMAP convention.
    const Eigen::Vector2d centroid(centroids.at<double>(k, 0) + 0.5,
                                   centroids.at<double>(k, 1) + 0.5);
    if (!OnOwnBeam(centroid, beams, own, options.roi_margin_px)) continue;
    candidates.push_back(k);
    if (best == 0 || summed_value[k] > summed_value[best]) best = k;
  }
  if (best == 0) return {};
  const auto box = [&](int k) {
    return cv::Rect(stats.at<int>(k, cv::CC_STAT_LEFT),
                    stats.at<int>(k, cv::CC_STAT_TOP),
                    stats.at<int>(k, cv::CC_STAT_WIDTH),
                    stats.at<int>(k, cv::CC_STAT_HEIGHT));
  };
  *rivals = box(best);
  for (const int k : candidates) {
    if (summed_value[k] >= kRivalFraction * summed_value[best]) {
      *rivals |= box(k);
    }
  }
  cv::Mat component;
  cv::compare(labels, best, component, cv::CMP_EQ);
  return component;
}

// Pixels to fit: centres, signal and whether each value is exact (0), a
// lower bound (1: clipped in the frame it adds) or an upper bound (-1).
// A bound costs nothing while the model respects it (censored least
// squares), so a clipped top still tells how high the spot is.
struct FitSamples {
  std::vector<Eigen::Vector2d> xs;
  std::vector<double> ys;
  std::vector<int8_t> bounds;
};

// Where the aux's print of a spot lies: the aux sees the spot at nearly
// the same image pixel (the lasers move with the camera), which the
// alignment maps to centre + offset in the ROI; the range changed a little
// between the frames, which moves it along the beam's image by some s.
struct PrintGeometry {
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  Eigen::Vector2d along = Eigen::Vector2d::UnitX();  // unit
};

// The model B + a exp(-q(x - mu) / 2) [+ a' exp(-q(x - mu') / 2)],
// q(d) = d^T P d, of the spot [and the aux's print, mu' = mu + offset +
// s along] on a constant, with parameters [B, P_11, P_12, P_22, a, mu_x,
// mu_y [, a', s]]; and its Levenberg-Marquardt fit. The spot and its print
// share a shape (one beam on one surface, seen from nearly one place) and
// the print's place follows the spot's up to s: that keeps the pair
// determined when they overlap. Fixed sizes keep the normal equations on
// the stack.
template <bool kWithPrint>
struct SpotFit {
  static constexpr int kParams = kWithPrint ? 9 : 7;
  using Vector = Eigen::Matrix<double, kParams, 1>;
  using Matrix = Eigen::Matrix<double, kParams, kParams>;

  PrintGeometry geometry;

  // The print's centre at theta.
  Eigen::Vector2d PrintMean(const Vector& theta) const {
    return theta.template segment<2>(5) + geometry.offset +
           theta(kParams - 1) * geometry.along;
  }

  double Value(const Vector& theta, const Eigen::Vector2d& x,
               Vector* jacobian) const {
    Eigen::Matrix2d precision;
    precision << theta(1), theta(2), theta(2), theta(3);
    double value = theta(0);
    jacobian->template head<4>() << 1.0, 0.0, 0.0, 0.0;
    // a exp(-q(x - mean) / 2), adding its derivatives by the shape; returns
    // a g P (x - mean), its derivative by the mean.
    const auto add = [&](double a, const Eigen::Vector2d& mean, double* g_out) {
      const Eigen::Vector2d d = x - mean;
      const Eigen::Vector2d pd = precision * d;
      const double q = d.dot(pd);
      // Single precision is ample for the model and twice as fast; the fit
      // spends most of its time here.
      const double g = q < 80.0 ? std::exp(static_cast<float>(-0.5 * q)) : 0.0;
      const double ag = a * g;
      value += ag;
      (*jacobian)(1) -= 0.5 * ag * d.x() * d.x();
      (*jacobian)(2) -= ag * d.x() * d.y();
      (*jacobian)(3) -= 0.5 * ag * d.y() * d.y();
      *g_out = g;
      return Eigen::Vector2d(ag * pd);
    };
    double g = 0.0;
    const Eigen::Vector2d by_mean =
        add(theta(4), theta.template segment<2>(5), &g);
    (*jacobian)(4) = g;
    jacobian->template segment<2>(5) = by_mean;
    if constexpr (kWithPrint) {
      const Eigen::Vector2d by_print_mean = add(theta(7), PrintMean(theta), &g);
      (*jacobian)(7) = g;
      jacobian->template segment<2>(5) += by_print_mean;
      (*jacobian)(8) = by_print_mean.dot(geometry.along);
    }
    return value;
  }

  static bool PrecisionPositive(const Vector& theta) {
    return theta.allFinite() && theta(1) > 0.0 &&
           theta(1) * theta(3) - Square(theta(2)) > 0.0;
  }

  // Cost, J^T J and J^T r at theta; false if not finite.
  bool Evaluate(const FitSamples& samples, const Vector& theta, double* cost,
                Matrix* normal, Vector* gradient) const {
    *cost = 0.0;
    normal->setZero();
    gradient->setZero();
    Vector row;
    for (size_t i = 0; i < samples.xs.size(); ++i) {
      const double residual = Value(theta, samples.xs[i], &row) - samples.ys[i];
      if (residual * samples.bounds[i] > 0.0) continue;  // bound respected
      *cost += residual * residual;
      normal->noalias() += row * row.transpose();
      *gradient += residual * row;
    }
    return std::isfinite(*cost);
  }

  // Levenberg-Marquardt from theta; false if the start is not finite. It
  // stops once a step moves the centre by less than 1e-3 px (far below any
  // noise) and the other parameters by less than 1e-4 of themselves, or
  // barely lowers the cost.
  bool Fit(const FitSamples& samples, Vector* theta) const {
    constexpr int kMaxIterations = 50;
    double cost;
    Matrix normal;
    Vector gradient;
    if (!Evaluate(samples, *theta, &cost, &normal, &gradient)) return false;
    double lambda = 1e-3;
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
      while (true) {
        Matrix damped = normal;
        damped.diagonal() += lambda * normal.diagonal().cwiseMax(1e-12);
        const Vector step = damped.ldlt().solve(-gradient);
        bool small = step.template segment<2>(5).norm() < 1e-3;
        for (int k = 1; k < kParams && small; ++k) {
          if (k != 5 && k != 6) {
            small = std::abs(step(k)) <= 1e-4 * std::abs((*theta)(k));
          }
        }
        const Vector candidate = *theta + step;
        double candidate_cost;
        Matrix candidate_normal;
        Vector candidate_gradient;
        if (PrecisionPositive(candidate) &&
            Evaluate(samples, candidate, &candidate_cost, &candidate_normal,
                     &candidate_gradient) &&
            candidate_cost < cost) {
          const double decrease = cost - candidate_cost;
          *theta = candidate;
          cost = candidate_cost;
          normal = candidate_normal;
          gradient = candidate_gradient;
          lambda = std::max(lambda * 0.1, 1e-9);
          if (small || decrease <= 1e-7 * cost) return true;
          break;
        }
        if (small || lambda > 1e10) return true;
        lambda *= 10.0;
      }
    }
    return true;
  }
};

// Fits the spot (and its print, if given, placed by `geometry`) to the
// samples from `start` and `print`; false if the fit failed.
bool FitSpot(const FitSamples& samples, double background,
             const GaussianSpot& start, const PrintGeometry& geometry,
             GaussianSpot* spot, GaussianSpot* print) {
  const Eigen::Matrix2d start_precision = start.covariance.inverse();
  const auto run = [&](auto fit) {
    using Fit = decltype(fit);
    typename Fit::Vector theta;
    theta(0) = background;
    theta(1) = start_precision(0, 0);
    theta(2) = start_precision(0, 1);
    theta(3) = start_precision(1, 1);
    theta(4) = start.amplitude;
    theta.template segment<2>(5) = start.mean;
    if constexpr (Fit::kParams == 9) {
      theta(7) = print->amplitude;
      theta(8) =
          (print->mean - start.mean - geometry.offset).dot(geometry.along);
    }
    if (!fit.Fit(samples, &theta)) return false;
    Eigen::Matrix2d precision;
    precision << theta(1), theta(2), theta(2), theta(3);
    spot->amplitude = theta(4);
    spot->mean = theta.template segment<2>(5);
    spot->covariance = precision.inverse();
    if constexpr (Fit::kParams == 9) {
      print->amplitude = theta(7);
      print->mean = fit.PrintMean(theta);
      print->covariance = spot->covariance;
    }
    return true;
  };
  if (print == nullptr) return run(SpotFit<false>());
  SpotFit<true> fit;
  fit.geometry = geometry;
  return run(fit);
}

// Adds the pixels under `window` to the fit samples: where `lower` is set
// the signal is only a lower bound of the truth (the frame it adds is
// clipped), where `upper` is set an upper bound (the frame it subtracts is
// clipped); where both, nothing is known. Either may be empty (none).
void AddSamples(const cv::Mat& window, const cv::Mat& signal,
                const cv::Mat& lower, const cv::Mat& upper,
                FitSamples* samples) {
  for (int r = 0; r < window.rows; ++r) {
    const uint8_t* in = window.ptr<uint8_t>(r);
    const float* value = signal.ptr<float>(r);
    for (int c = 0; c < window.cols; ++c) {
      if (!in[c]) continue;
      const bool is_lower = !lower.empty() && lower.at<uint8_t>(r, c);
      const bool is_upper = !upper.empty() && upper.at<uint8_t>(r, c);
      if (is_lower && is_upper) continue;
      samples->xs.emplace_back(c + 0.5, r + 0.5);
      samples->ys.push_back(value[c]);
      samples->bounds.push_back(is_lower ? 1 : is_upper ? -1 : 0);
    }
  }
}

// The low-passed texture-removed image of LSD steps 5-6: max(main - aux, 0)
// per channel (sign -1: max(aux - main, 0), where the aux's print shows),
// or `main` itself without an aux.
cv::Mat CleanImage(const Roi& roi, const cv::Mat& main, int sign,
                   const SpotDetectorOptions& options) {
  if (roi.aux.empty()) return LowPass(main, options.lowpass_sigma_px);
  cv::Mat clean;
  cv::max(sign > 0 ? cv::Mat(main - roi.aux) : cv::Mat(roi.aux - main), 0.0,
          clean);
  return LowPass(clean, options.lowpass_sigma_px);
}

// The fit's signal: the low-passed signed difference in one channel (the
// aux's print negative), or that channel of `main` without an aux.
cv::Mat SignalImage(const Roi& roi, const cv::Mat& main, int sign, int channel,
                    const SpotDetectorOptions& options) {
  cv::Mat signal = Channel(main, channel);
  if (!roi.aux.empty()) {
    signal = sign * (signal - Channel(roi.aux, channel));
  }
  return LowPass(signal, options.lowpass_sigma_px);
}

// V (the largest channel) of a CV_32FC3 image.
cv::Mat ValueImage(const cv::Mat& image) {
  std::vector<cv::Mat> channels;
  cv::split(image, channels);
  cv::Mat value = cv::max(channels[0], channels[1]);
  return cv::max(value, channels[2]);
}

Background MeasureBackground(const cv::Mat& clean, const cv::Mat& valid) {
  Background background;
  for (int c = 0; c < 3; ++c) {
    background.levels[c] = RobustStats(Channel(clean, c), valid).median;
  }
  background.value = RobustStats(ValueImage(clean - background.levels), valid);
  return background;
}

struct Run {
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
std::optional<Run> DetectInRoi(const Roi& roi, const cv::Mat& main, int sign,
                               const Background& background, double extra_sigma,
                               int channel,
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
  Run run;
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

// Standard normal quantiles at (i + 0.5) / 2^16 (Acklam's rational
// approximation, relative error < 1.2e-9): the Monte Carlo's noise takes
// four 16-bit indices from each SplitMix64 draw, ~20x cheaper than
// Box-Muller, with tails cut at 4.2 σ (probability 3e-5).
const std::vector<float>& NormalQuantiles() {
  static const std::vector<float> table = [] {
    constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                            -2.759285104469687e+02, 1.383577518672690e+02,
                            -3.066479806614716e+01, 2.506628277459239e+00};
    constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                            -1.556989798598866e+02, 6.680131188771972e+01,
                            -1.328068155288572e+01};
    constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                            -2.400758277161838e+00, -2.549732539343734e+00,
                            4.374664141464968e+00,  2.938163982698783e+00};
    constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                            2.445134137142996e+00, 3.754408661907416e+00};
    const auto tail = [&](double q) {
      return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q +
              c[5]) /
             ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    };
    std::vector<float> values(1 << 16);
    for (size_t i = 0; i < values.size(); ++i) {
      const double p = (i + 0.5) / values.size();
      double x;
      if (p < 0.02425) {
        x = tail(std::sqrt(-2.0 * std::log(p)));
      } else if (p > 1.0 - 0.02425) {
        x = -tail(std::sqrt(-2.0 * std::log(1.0 - p)));
      } else {
        const double q = p - 0.5;
        const double r = q * q;
        x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r +
             a[5]) *
            q /
            (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r +
             1.0);
      }
      values[i] = static_cast<float>(x);
    }
    return values;
  }();
  return table;
}

// `image` (CV_32FC3) plus i.i.d. N(0, sigma^2) in every channel, from the
// counter-based key (so any thread gives the same noise).
cv::Mat WithNoise(const cv::Mat& image, double sigma, uint64_t key) {
  const std::vector<float>& quantiles = NormalQuantiles();
  cv::Mat noisy = image.clone();
  SplitMix64Stream random(key);
  const float s = static_cast<float>(sigma);
  for (int r = 0; r < noisy.rows; ++r) {
    float* row = noisy.ptr<float>(r);
    const int n = noisy.cols * 3;
    uint64_t bits = 0;
    for (int i = 0; i < n; ++i) {
      if (i % 4 == 0) bits = random.Next();
      row[i] += s * quantiles[bits & 0xFFFF];
      bits >>= 16;
    }
  }
  return noisy;
}

// §5.4 without an aux: robust σ of the image's second differences
// (Immerkær's 3x3 operator, whose response to white noise has σ 6 σ_pixel),
// in the ROIs; edges of the texture are outliers that the median ignores.
double NoiseFromImage(const std::vector<Roi>& rois) {
  const cv::Mat kernel =
      (cv::Mat_<float>(3, 3) << 1, -2, 1, -2, 4, -2, 1, -2, 1);
  std::vector<float> values;
  for (const Roi& roi : rois) {
    if (!roi.problem.empty()) continue;
    cv::Mat response;
    cv::filter2D(roi.main, response, CV_32F, kernel, cv::Point(-1, -1), 0,
                 cv::BORDER_REPLICATE);
    const cv::Mat flat = response.reshape(1, 1);
    for (int i = 0; i < flat.cols; ++i) {
      values.push_back(std::abs(flat.at<float>(0, i)));
    }
  }
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return kMadToSigma * *middle / 6.0;
}

// §5.4 with the aux: robust σ of the aligned, matched difference in the
// laser's weakest channel; when both frames are equally noisy, that is
// σ sqrt(1 + g^2) with g the aligned aux's noise gain. The median over the
// ROIs.
double NoiseFromDifference(const std::vector<Roi>& rois,
                           const SpotDetectorOptions& options) {
  std::vector<double> sigmas;
  for (const Roi& roi : rois) {
    if (!roi.problem.empty() || roi.aux.empty()) continue;
    const cv::Mat difference = Channel(roi.main, roi.colour.weakest) -
                               Channel(roi.aux, roi.colour.weakest);
    const double sigma = RobustStats(difference, roi.valid).sigma;
    sigmas.push_back(options.aux_equally_noisy
                         ? sigma / std::sqrt(1.0 + Square(roi.aux_noise_gain))
                         : sigma);
  }
  if (sigmas.empty()) return -1.0;
  std::nth_element(sigmas.begin(), sigmas.begin() + sigmas.size() / 2,
                   sigmas.end());
  return sigmas[sigmas.size() / 2];
}

void CheckImages(const cv::Mat& image, const cv::Mat* aux, const Camera& camera,
                 const char* what) {
  if (image.empty()) throw ErrorAt(what, ": empty image");
  if (image.type() != CV_8UC3) {
    throw ErrorAt(what, ": expected an 8-bit BGR image (CV_8UC3), got ",
                  image.channels(), " channel(s) of depth ", image.depth());
  }
  CheckCameraModelParams(camera.model_id, camera.params.size());
  if (static_cast<uint64_t>(image.cols) != camera.width ||
      static_cast<uint64_t>(image.rows) != camera.height) {
    throw ErrorAt(what, ": the image is ", image.cols, "x", image.rows,
                  ", its camera ", camera.width, "x", camera.height);
  }
  if (aux != nullptr && !aux->empty()) {
    if (aux->type() != CV_8UC3) {
      throw ErrorAt(what,
                    ": expected an 8-bit BGR auxiliary image (CV_8UC3), got ",
                    aux->channels(), " channel(s) of depth ", aux->depth());
    }
    if (aux->size() != image.size()) {
      throw ErrorAt(what, ": the auxiliary image is ", aux->cols, "x",
                    aux->rows, ", the image ", image.cols, "x", image.rows);
    }
  }
}

// LSD step 1: the ROI of each laser, with its image patch.
std::vector<Roi> PredictRois(const cv::Mat& image, const Camera& camera,
                             const LaserSetup& setup,
                             const SpotDetectorOptions& options) {
  std::vector<Roi> rois(setup.lasers.size());
  std::vector<std::vector<Eigen::Vector2d>> beams;
  for (const Laser& laser : setup.lasers) {
    beams.push_back(BeamImage(camera, laser, options));
  }
  const cv::Rect image_rect(0, 0, image.cols, image.rows);
  for (size_t l = 0; l < setup.lasers.size(); ++l) {
    Roi& roi = rois[l];
    roi.laser = l;
    roi.colour = ColourOf(setup.lasers[l]);
    const std::vector<Eigen::Vector2d>& beam = beams[l];
    cv::Rect rect;
    if (!beam.empty()) {
      Eigen::Vector2d low = beam[0];
      Eigen::Vector2d high = beam[0];
      for (const Eigen::Vector2d& p : beam) {
        low = low.cwiseMin(p);
        high = high.cwiseMax(p);
      }
      const double margin = options.roi_margin_px;
      const auto clamp = [](double v) {
        return static_cast<int>(std::clamp(v, -1e9, 1e9));
      };
      const int x0 = clamp(std::floor(low.x() - margin));
      const int y0 = clamp(std::floor(low.y() - margin));
      const int x1 = clamp(std::ceil(high.x() + margin));
      const int y1 = clamp(std::ceil(high.y() + margin));
      rect = cv::Rect(x0, y0, x1 - x0, y1 - y0) & image_rect;
    }
    if (rect.area() == 0) {
      char problem[160];
      std::snprintf(problem, sizeof(problem),
                    "outside the image (the beam between %g and %g m depth "
                    "does not project into it)",
                    options.min_range_m, options.max_range_m);
      roi.problem = problem;
      continue;
    }
    roi.rect = rect;
    for (const std::vector<Eigen::Vector2d>& image_beam : beams) {
      roi.beams.emplace_back();
      for (const Eigen::Vector2d& p : image_beam) {
        roi.beams.back().push_back(p - Eigen::Vector2d(rect.x, rect.y));
      }
    }
    image(rect).convertTo(roi.main, CV_32FC3);
    roi.valid = cv::Mat(rect.size(), CV_8U, cv::Scalar(255));
  }
  return rois;
}

// LSD steps 2-4, the nominal backgrounds of the thresholds, the aux's
// print and the nominal detection.
std::optional<Run> PrepareRoi(const cv::Mat& image, const cv::Mat& aux,
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
    const std::optional<Run> print = DetectInRoi(
        *roi, roi->main, -1, roi->print_background, 0.0, -1, options);
    if (print) {
      roi->print = print->spot;
      roi->print_window = print->window;
    }
  }
  const std::optional<Run> nominal =
      DetectInRoi(*roi, roi->main, 1, roi->background, 0.0, -1, options);
  if (nominal) {
    roi->channel = nominal->channel;
    roi->nominal_spot = nominal->spot;
    roi->nominal_print = nominal->print;
  }
  return nominal;
}

// The part of `roi` inside `window` (ROI coordinates), for the Monte Carlo
// iterations: they need only the neighbourhood of the nominal detection.
Roi Crop(const Roi& roi, const cv::Rect& window) {
  Roi out;
  out.rect = window + roi.rect.tl();
  out.laser = roi.laser;
  out.colour = roi.colour;
  const Eigen::Vector2d shift(window.x, window.y);
  const auto shifted =
      [&](const std::vector<std::vector<Eigen::Vector2d>>& in) {
        std::vector<std::vector<Eigen::Vector2d>> lines;
        for (const std::vector<Eigen::Vector2d>& line : in) {
          lines.emplace_back();
          for (const Eigen::Vector2d& p : line)
            lines.back().push_back(p - shift);
        }
        return lines;
      };
  out.beams = shifted(roi.beams);
  out.aux_beams = shifted(roi.aux_beams);
  out.main = roi.main(window);
  if (!roi.aux.empty()) out.aux = roi.aux(window);
  out.valid = roi.valid(window);
  for (int c = 0; c < 3; ++c) {
    out.clipped_main[c] = roi.clipped_main[c](window);
    if (!roi.aux.empty()) out.clipped_aux[c] = roi.clipped_aux[c](window);
  }
  out.background = roi.background;
  out.channel = roi.channel;
  for (const auto& [from, to] :
       {std::pair(&roi.print, &out.print),
        std::pair(&roi.nominal_spot, &out.nominal_spot),
        std::pair(&roi.nominal_print, &out.nominal_print)}) {
    *to = *from;
    if (*to) (*to)->mean -= shift;
  }
  if (roi.print) out.print_window = roi.print_window(window);
  return out;
}

uint64_t IterationKey(uint64_t seed, size_t laser, int iteration) {
  return SplitMix64(SplitMix64(SplitMix64(seed) + laser) +
                    static_cast<uint64_t>(iteration));
}

std::string Percent(double rate) {
  char text[16];
  std::snprintf(text, sizeof(text), "%.0f %%", 100.0 * rate);
  return text;
}

// Moments of the mixture of the detections' N(centre, Σc) (§5.3 step 4:
// equal to the Unscented Transform's merge of their sigma points).
void Merge(const std::vector<Detection>& detections, DetectedSpot* spot) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Detection& d : detections) mean += d.centre;
  mean /= static_cast<double>(detections.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const Detection& d : detections) {
    covariance +=
        d.centre_cov + (d.centre - mean) * (d.centre - mean).transpose();
  }
  spot->pixel = mean;
  spot->covariance = covariance / static_cast<double>(detections.size());
}

}  // namespace

void SpotDetectorOptions::Check() const {
  const auto fail = [](const char* field, double value, const char* rule) {
    throw ErrorAt("spot detector options: ", field, " = ", value, ": ", rule);
  };
  if (!(min_range_m > 0.0)) fail("min_range_m", min_range_m, "must be > 0");
  if (!(max_range_m > min_range_m && std::isfinite(max_range_m))) {
    fail("max_range_m", max_range_m, "must be finite and > min_range_m");
  }
  if (roi_margin_px < 0) fail("roi_margin_px", roi_margin_px, "must be >= 0");
  if (aux_search_px < 0) fail("aux_search_px", aux_search_px, "must be >= 0");
  if (!(min_alignment_ncc >= -1.0 && min_alignment_ncc <= 1.0)) {
    fail("min_alignment_ncc", min_alignment_ncc, "must be in [-1, 1]");
  }
  if (ecc_iterations < 1)
    fail("ecc_iterations", ecc_iterations, "must be >= 1");
  if (!(lowpass_sigma_px >= 0.0 && lowpass_sigma_px <= 10.0)) {
    fail("lowpass_sigma_px", lowpass_sigma_px, "must be in [0, 10]");
  }
  if (!(hue_tolerance_deg > 0.0 && hue_tolerance_deg <= 180.0)) {
    fail("hue_tolerance_deg", hue_tolerance_deg, "must be in (0, 180]");
  }
  if (!(min_saturation >= 0.0 && min_saturation <= 1.0)) {
    fail("min_saturation", min_saturation, "must be in [0, 1]");
  }
  if (!(value_threshold_sigmas >= 0.0 &&
        std::isfinite(value_threshold_sigmas))) {
    fail("value_threshold_sigmas", value_threshold_sigmas, "must be >= 0");
  }
  if (!(min_value >= 0.0 && min_value < 255.0)) {
    fail("min_value", min_value, "must be in [0, 255)");
  }
  if (opening_radius_px < 0 || opening_radius_px > 10) {
    fail("opening_radius_px", opening_radius_px, "must be in [0, 10]");
  }
  if (min_area_px < 1) fail("min_area_px", min_area_px, "must be >= 1");
  if (max_area_px < min_area_px) {
    fail("max_area_px", max_area_px, "must be >= min_area_px");
  }
  if (fit_margin_px < 0 || fit_margin_px > 20) {
    fail("fit_margin_px", fit_margin_px, "must be in [0, 20]");
  }
  if (!(saturation_level > 0.0 && saturation_level <= 255.0)) {
    fail("saturation_level", saturation_level, "must be in (0, 255]");
  }
  if (!(top_fraction > 0.0 && top_fraction < 1.0)) {
    fail("top_fraction", top_fraction, "must be in (0, 1)");
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    fail("confidence", confidence, "must be in (0, 1)");
  }
  if (monte_carlo_iterations < 0) {
    fail("monte_carlo_iterations", monte_carlo_iterations, "must be >= 0");
  }
  if (!(min_detection_rate >= 0.0 && min_detection_rate <= 1.0)) {
    fail("min_detection_rate", min_detection_rate, "must be in [0, 1]");
  }
  if (!(noise_sigma < 255.0) || std::isnan(noise_sigma)) {
    fail("noise_sigma", noise_sigma, "must be < 255 (< 0: estimate)");
  }
}

std::vector<DetectedSpot> DetectSpots(const cv::Mat& image, const cv::Mat& aux,
                                      const Camera& camera,
                                      const LaserSetup& setup,
                                      const SpotDetectorOptions& options,
                                      uint64_t seed) {
  CheckImages(image, &aux, camera, "DetectSpots");
  options.Check();
  setup.Check();
  std::vector<Roi> rois = PredictRois(image, camera, setup, options);
  const size_t num_lasers = rois.size();
  const int iterations = options.monte_carlo_iterations;
  const double centre_scale = 2.0 *
                              std::log(1.0 / (1.0 - options.top_fraction)) /
                              (-2.0 * std::log(1.0 - options.confidence));
  const auto to_detection = [&](const Roi& roi, const GaussianSpot& spot) {
    Detection detection;
    detection.centre = spot.mean + Eigen::Vector2d(roi.rect.x, roi.rect.y);
    detection.centre_cov = centre_scale * spot.covariance;
    return detection;
  };

  std::vector<std::optional<Run>> nominal(num_lasers);
  std::vector<Roi> windows(num_lasers);
  std::vector<std::optional<GaussianSpot>> runs(num_lasers * iterations);
  double noise_sigma = options.noise_sigma;
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads
                                                : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(size_t{0}, num_lasers, [&](size_t l) {
      if (!rois[l].problem.empty()) return;
      nominal[l] = PrepareRoi(image, aux, options, &rois[l]);
      if (!nominal[l]) return;
      // The iterations' window: the nominal fit and its rivals, with room
      // for the low-pass and the fit margin.
      const int grow =
          options.fit_margin_px +
          static_cast<int>(std::ceil(4.0 * options.lowpass_sigma_px)) + 2;
      const cv::Rect extent = nominal[l]->extent;
      windows[l] = Crop(
          rois[l], cv::Rect(extent.x - grow, extent.y - grow,
                            extent.width + 2 * grow, extent.height + 2 * grow) &
                       cv::Rect(cv::Point(0, 0), rois[l].rect.size()));
    });
    if (noise_sigma < 0.0) {
      noise_sigma = NoiseFromDifference(rois, options);
      if (noise_sigma < 0.0) noise_sigma = NoiseFromImage(rois);
    }
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, runs.size(), 4),
        [&](const tbb::blocked_range<size_t>& range) {
          for (size_t i = range.begin(); i != range.end(); ++i) {
            const size_t l = i / iterations;
            const int n = static_cast<int>(i % iterations);
            if (!nominal[l]) continue;
            const Roi& window = windows[l];
            const std::optional<Run> run = DetectInRoi(
                window,
                WithNoise(window.main, noise_sigma, IterationKey(seed, l, n)),
                1, window.background, noise_sigma, window.channel, options);
            if (run) runs[i] = run->spot;
          }
        });
  });

  std::vector<DetectedSpot> spots(num_lasers);
  for (size_t l = 0; l < num_lasers; ++l) {
    DetectedSpot& spot = spots[l];
    const Roi& roi = rois[l];
    spot.laser = setup.lasers[l].name;
    if (!roi.problem.empty()) {
      spot.problem = roi.problem;
      continue;
    }
    std::vector<Detection> detections;
    for (int n = 0; n < iterations; ++n) {
      const std::optional<GaussianSpot>& run = runs[l * iterations + n];
      if (!run) continue;
      detections.push_back(to_detection(windows[l], *run));
      spot.iterations.emplace_back(detections.back().centre,
                                   detections.back().centre_cov);
    }
    spot.detected = nominal[l].has_value();
    if (iterations == 0) {
      spot.detection_rate = spot.detected ? 1.0 : 0.0;
      if (spot.detected) {
        detections.push_back(to_detection(roi, nominal[l]->spot));
      }
    } else {
      spot.detection_rate = static_cast<double>(detections.size()) / iterations;
    }
    if (!detections.empty()) {
      Merge(detections, &spot);
    } else if (spot.detected) {
      const Detection only = to_detection(roi, nominal[l]->spot);
      spot.pixel = only.centre;
      spot.covariance = only.centre_cov;
    }
    spot.stable =
        spot.detected && spot.detection_rate >= options.min_detection_rate;
    if (!spot.detected) {
      spot.problem = "not detected";
    } else if (!spot.stable) {
      spot.problem = "unstable: detected in " + Percent(spot.detection_rate) +
                     " of iterations";
    }
    if (!spot.stable && !roi.texture_note.empty()) {
      spot.problem += " (" + roi.texture_note + ")";
    }
  }
  return spots;
}

std::vector<DetectedSpot> DetectBrightestPixel(
    const cv::Mat& image, const Camera& camera, const LaserSetup& setup,
    const SpotDetectorOptions& options) {
  CheckImages(image, nullptr, camera, "DetectBrightestPixel");
  options.Check();
  setup.Check();
  const std::vector<Roi> rois = PredictRois(image, camera, setup, options);
  std::vector<DetectedSpot> spots(rois.size());
  for (size_t l = 0; l < rois.size(); ++l) {
    const Roi& roi = rois[l];
    DetectedSpot& spot = spots[l];
    spot.laser = setup.lasers[l].name;
    if (!roi.problem.empty()) {
      spot.problem = roi.problem;
      continue;
    }
    const cv::Mat mask = [&] {
      SpotDetectorOptions no_opening = options;
      no_opening.opening_radius_px = 0;
      return ColourMask(roi.main, roi.valid, roi.colour, 0.0, no_opening);
    }();
    // 8-bit levels tie often (a saturated spot is a plateau): the centre of
    // the brightest pixels.
    double brightest = -1.0;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (int r = 0; r < roi.main.rows; ++r) {
      for (int c = 0; c < roi.main.cols; ++c) {
        const Eigen::Vector2d centre(c + 0.5, r + 0.5);
        const double value = roi.main.at<cv::Vec3f>(r, c)[roi.colour.dominant];
        if (value < brightest || !mask.at<uint8_t>(r, c) ||
            !OnOwnBeam(centre, roi.beams, roi.laser, options.roi_margin_px)) {
          continue;
        }
        if (value > brightest) {
          brightest = value;
          sum.setZero();
          count = 0;
        }
        if (value == brightest) {
          sum += centre;
          ++count;
        }
      }
    }
    if (count == 0) {
      spot.problem = "not detected";
      continue;
    }
    spot.detected = true;
    spot.stable = true;
    spot.detection_rate = 1.0;
    spot.pixel = sum / count + Eigen::Vector2d(roi.rect.x, roi.rect.y);
    spot.covariance = Eigen::Matrix2d::Identity() / 12.0;
  }
  return spots;
}

namespace {

// The ellipse of `covariance` at Mahalanobis `radius` around `centre`
// (COLMAP pixels, scaled by `zoom` after shifting by -origin), drawn with
// sub-pixel precision.
void DrawEllipse(cv::Mat* canvas, const Eigen::Vector2d& centre,
                 const Eigen::Matrix2d& covariance, double radius,
                 const Eigen::Vector2d& origin, double zoom,
                 const cv::Scalar& colour) {
  constexpr int kShift = 4;
  constexpr double kUnit = 1 << kShift;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  const Eigen::Vector2d axes =
      radius * zoom * eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Vector2d major = eigen.eigenvectors().col(1);
  // OpenCV draws pixel (c, r) centred on (c, r): half a pixel off COLMAP.
  const Eigen::Vector2d at =
      (centre - origin) * zoom - Eigen::Vector2d::Constant(0.5);
  cv::ellipse(*canvas,
              cv::Point(static_cast<int>(std::lround(at.x() * kUnit)),
                        static_cast<int>(std::lround(at.y() * kUnit))),
              cv::Size(static_cast<int>(std::lround(axes(1) * kUnit)),
                       static_cast<int>(std::lround(axes(0) * kUnit))),
              std::atan2(major.y(), major.x()) * 180.0 / M_PI, 0.0, 360.0,
              colour, 1, cv::LINE_AA, kShift);
}

cv::Point ToPoint(const Eigen::Vector2d& pixel, const Eigen::Vector2d& origin,
                  double zoom) {
  const Eigen::Vector2d at = (pixel - origin) * zoom;
  return {static_cast<int>(std::floor(at.x())),
          static_cast<int>(std::floor(at.y()))};
}

const cv::Scalar kColour68(80, 255, 80);
const cv::Scalar kColour95(0, 220, 255);
const cv::Scalar kColourIteration(255, 200, 120);
const cv::Scalar kColourProblem(40, 40, 255);

// Draws one spot's marks at `zoom` with `origin` at the canvas corner.
void DrawSpot(cv::Mat* canvas, const DetectedSpot& spot,
              const Eigen::Vector2d& origin, double zoom) {
  if (!spot.iterations.empty()) {
    // Half-transparent, so that the cloud does not hide the spot.
    cv::Mat dots = canvas->clone();
    for (const auto& [centre, covariance] : spot.iterations) {
      cv::circle(dots, ToPoint(centre, origin, zoom),
                 std::max(1, static_cast<int>(zoom / 4)), kColourIteration, -1,
                 cv::LINE_AA);
    }
    cv::addWeighted(dots, 0.5, *canvas, 0.5, 0.0, *canvas);
  }
  const cv::Scalar marker = spot.stable ? kColour68 : kColourProblem;
  if (spot.stable) {
    DrawEllipse(canvas, spot.pixel, spot.covariance, kRadius68, origin, zoom,
                kColour68);
    DrawEllipse(canvas, spot.pixel, spot.covariance, kRadius95, origin, zoom,
                kColour95);
  }
  // A cross with a gap, visible at any zoom without hiding the spot.
  const cv::Point at = ToPoint(spot.pixel, origin, zoom);
  const int gap = std::max(6, static_cast<int>(3 * zoom));
  const int arm = gap + 8;
  cv::line(*canvas, at + cv::Point(gap, 0), at + cv::Point(arm, 0), marker, 1);
  cv::line(*canvas, at - cv::Point(gap, 0), at - cv::Point(arm, 0), marker, 1);
  cv::line(*canvas, at + cv::Point(0, gap), at + cv::Point(0, arm), marker, 1);
  cv::line(*canvas, at - cv::Point(0, gap), at - cv::Point(0, arm), marker, 1);
  const std::string label =
      spot.stable ? spot.laser : spot.laser + ": " + spot.problem;
  cv::putText(*canvas, label, at + cv::Point(arm + 2, -arm),
              cv::FONT_HERSHEY_SIMPLEX, 0.4, marker, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat DrawSpotOverlay(const cv::Mat& image,
                        const std::vector<DetectedSpot>& spots) {
  if (image.empty()) throw ErrorAt("DrawSpotOverlay: empty image");
  cv::Mat canvas;
  if (image.type() == CV_8UC3) {
    canvas = image.clone();
  } else if (image.type() == CV_8UC1) {
    cv::cvtColor(image, canvas, cv::COLOR_GRAY2BGR);
  } else {
    throw ErrorAt("DrawSpotOverlay: expected an 8-bit image, got type ",
                  image.type());
  }
  const cv::Mat source = canvas.clone();
  std::vector<const DetectedSpot*> located;
  int undetected_line = 0;
  for (const DetectedSpot& spot : spots) {
    if (spot.detected) {
      DrawSpot(&canvas, spot, Eigen::Vector2d::Zero(), 1.0);
      located.push_back(&spot);
    } else {
      cv::putText(canvas, spot.laser + ": " + spot.problem,
                  cv::Point(8, 18 + 16 * undetected_line++),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45, kColourProblem, 1,
                  cv::LINE_AA);
    }
  }
  if (located.empty()) return canvas;

  // The strip of magnified crops, kCrop source pixels square each.
  constexpr int kCrop = 24;
  constexpr int kZoom = 8;
  constexpr int kTile = kCrop * kZoom;
  const int per_row = std::max(1, canvas.cols / kTile);
  const int rows = (static_cast<int>(located.size()) + per_row - 1) / per_row;
  cv::Mat out(canvas.rows + rows * kTile, std::max(canvas.cols, kTile), CV_8UC3,
              cv::Scalar::all(0));
  canvas.copyTo(out(cv::Rect(0, 0, canvas.cols, canvas.rows)));
  for (size_t i = 0; i < located.size(); ++i) {
    const DetectedSpot& spot = *located[i];
    const int x0 = static_cast<int>(std::floor(spot.pixel.x())) - kCrop / 2;
    const int y0 = static_cast<int>(std::floor(spot.pixel.y())) - kCrop / 2;
    const cv::Rect want(x0, y0, kCrop, kCrop);
    const cv::Rect have = want & cv::Rect(0, 0, source.cols, source.rows);
    cv::Mat crop(kCrop, kCrop, CV_8UC3, cv::Scalar::all(0));
    if (have.area() > 0) {
      source(have).copyTo(
          crop(cv::Rect(have.x - x0, have.y - y0, have.width, have.height)));
    }
    cv::Mat tile;
    cv::resize(crop, tile, cv::Size(kTile, kTile), 0, 0, cv::INTER_NEAREST);
    DrawSpot(&tile, spot, Eigen::Vector2d(x0, y0), kZoom);
    const int slot = static_cast<int>(i);
    tile.copyTo(
        out(cv::Rect((slot % per_row) * kTile,
                     canvas.rows + (slot / per_row) * kTile, kTile, kTile)));
  }
  return out;
}

}  // namespace uw
