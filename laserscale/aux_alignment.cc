#include "laserscale/aux_alignment.h"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "laserscale/spot_levels.h"

namespace uw::lsd {

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

double SameSceneNcc(const cv::Mat& patch) {
  std::vector<float> values;
  AppendSecondDifferences(patch, &values);
  // Exact zeros are the flattened highlights' constant pixels
  // (FlattenHighlights), not noise: they would pull the noise down and the
  // NCC expected of the same scene up.
  values.erase(std::remove(values.begin(), values.end(), 0.0f), values.end());
  const double noise_variance = Square(SecondDifferenceSigma(&values));
  cv::Scalar mean;
  cv::Scalar deviation;
  cv::meanStdDev(patch, mean, deviation);
  const double texture_variance =
      std::max(0.0, Square(deviation[0]) - noise_variance);
  return texture_variance > 0.0
             ? texture_variance / (texture_variance + noise_variance)
             : 0.0;
}

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
    // Noise alone lowers the NCC of the same scene (to 0.4 on uwsim's
    // plane at sensor noise 6): only where the texture would have matched
    // well does a low NCC say that the aux shows another scene.
    constexpr double kTellingNcc = 0.75;
    const double same_scene = SameSceneNcc(templ);
    roi->aux_mismatch = same_scene >= kTellingNcc;
    roi->texture_note = fmt::format(
        "texture not removed: the aux does not match (NCC {:.2f}; the same "
        "scene would give {:.2f}{})",
        std::isfinite(best) ? best : 0.0, same_scene,
        roi->aux_mismatch ? "" : ": too noisy to tell");
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

}  // namespace uw::lsd
