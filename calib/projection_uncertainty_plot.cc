#include "calib/projection_uncertainty_plot.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "common/util/error.h"

namespace uw {
namespace {

// mrcal's contour step: the round number (1, 2 or 5 times a power of ten)
// nearest a tenth of the colour range.
double ContourStep(double colour_max) {
  const double wanted = colour_max / 10.0;
  const double decade = std::pow(10.0, std::floor(std::log10(wanted)));
  double best = decade;
  for (const double m : {2.0, 5.0, 10.0}) {
    if (std::abs(m * decade - wanted) < std::abs(best - wanted)) {
      best = m * decade;
    }
  }
  return best;
}

std::string Format(double value) { return fmt::format("{:.3g}", value); }

// The map at image pixel (x, y): bilinear between its samples; a sample
// that does not unproject counts as very uncertain, as mrcal counts it.
double Interpolate(const ProjectionUncertaintyMap& map, double x, double y) {
  const auto locate = [](const std::vector<double>& samples, double value,
                         int* cell, double* fraction) {
    const int last = static_cast<int>(samples.size()) - 1;
    const double step = samples[last] / last;
    const double u = std::clamp(value / step, 0.0, static_cast<double>(last));
    *cell = std::min(static_cast<int>(u), last - 1);
    *fraction = u - *cell;
  };
  int i = 0;
  int j = 0;
  double fy = 0.0;
  double fx = 0.0;
  locate(map.y_px, y, &i, &fy);
  locate(map.x_px, x, &j, &fx);
  const auto at = [&](int r, int c) {
    const double value = map.stdev_px(r, c);
    return std::isfinite(value) ? value : 1e6;
  };
  return (1 - fy) * ((1 - fx) * at(i, j) + fx * at(i, j + 1)) +
         fy * ((1 - fx) * at(i + 1, j) + fx * at(i + 1, j + 1));
}

void Text(cv::Mat* image, const std::string& text, cv::Point origin,
          double scale, const cv::Scalar& colour, bool boxed = false) {
  if (boxed) {
    int baseline = 0;
    const cv::Size size =
        cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
    cv::rectangle(*image,
                  cv::Rect(origin.x - 2, origin.y - size.height - 2,
                           size.width + 4, size.height + baseline + 3),
                  cv::Scalar(255, 255, 255), cv::FILLED);
  }
  cv::putText(*image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1,
              cv::LINE_AA);
}

}  // namespace

cv::Mat RenderProjectionUncertainty(const ProjectionUncertaintyMap& map,
                                    int image_width, int image_height,
                                    const std::string& title,
                                    double colour_max_px) {
  if (map.x_px.size() < 2 || map.y_px.size() < 2 ||
      map.stdev_px.rows() != static_cast<int>(map.y_px.size()) ||
      map.stdev_px.cols() != static_cast<int>(map.x_px.size())) {
    throw Error("projection uncertainty plot: the map has no grid");
  }
  if (image_width < 2 || image_height < 2 || !(colour_max_px > 0.0)) {
    throw Error(
        "projection uncertainty plot: the image size and colour range must "
        "be positive");
  }
  const double scale = 900.0 / image_width;
  const int width = static_cast<int>(std::lround(image_width * scale));
  const int height = static_cast<int>(std::lround(image_height * scale));
  cv::Mat1d field(height, width);
  cv::Mat1b level(height, width);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const double value =
          Interpolate(map, (u + 0.5) / scale - 0.5, (v + 0.5) / scale - 0.5);
      field(v, u) = value;
      level(v, u) = cv::saturate_cast<uchar>(
          std::min(value / colour_max_px, 1.0) * 255.0);
    }
  }
  cv::Mat heat;
  cv::applyColorMap(level, heat, cv::COLORMAP_VIRIDIS);

  // Contours as mrcal draws them, from the top of the range down; the
  // regions' outlines along the image's edge are no contour.
  const double step = ContourStep(colour_max_px);
  const auto on_edge = [&](const cv::Point& p) {
    return p.x == 0 || p.y == 0 || p.x == width - 1 || p.y == height - 1;
  };
  std::vector<std::pair<cv::Point, std::string>> labels;
  for (int k = 1; k * step <= colour_max_px * (1.0 + 1e-9); ++k) {
    const double contour = k * step;
    const cv::Mat mask = field >= contour;
    std::vector<std::vector<cv::Point>> outlines;
    cv::findContours(mask, outlines, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    for (const std::vector<cv::Point>& outline : outlines) {
      std::vector<cv::Point> inside;
      for (size_t k = 0; k < outline.size(); ++k) {
        const cv::Point& a = outline[k];
        const cv::Point& b = outline[(k + 1) % outline.size()];
        if (on_edge(a) || on_edge(b)) continue;
        cv::line(heat, a, b, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
        inside.push_back(a);
      }
      if (inside.size() < 80) continue;
      // A label where it hides no other: the contour's middle, else a
      // point nearer one of its ends.
      for (const double at : {0.5, 0.25, 0.75, 0.125, 0.875}) {
        const cv::Point where =
            inside[static_cast<size_t>(at * (inside.size() - 1))];
        bool clear = true;
        for (const auto& label : labels) {
          clear = clear && (std::abs(label.first.x - where.x) > 34 ||
                            std::abs(label.first.y - where.y) > 16);
        }
        if (clear) {
          labels.emplace_back(where, Format(contour));
          break;
        }
      }
    }
  }
  for (const auto& [where, text] : labels) {
    Text(&heat, text, where + cv::Point(-8, 4), 0.35, cv::Scalar(0, 0, 0),
         true);
  }

  // The canvas: title above, colour bar to the right.
  const int top = 58;
  const int left = 12;
  const int bar_width = 18;
  const int right = 80;
  cv::Mat canvas(top + height + 12, left + width + right, CV_8UC3,
                 cv::Scalar(255, 255, 255));
  heat.copyTo(canvas(cv::Rect(left, top, width, height)));
  cv::rectangle(canvas, cv::Rect(left - 1, top - 1, width + 2, height + 2),
                cv::Scalar(0, 0, 0));
  Text(&canvas, title, {left, 22}, 0.5, cv::Scalar(0, 0, 0));
  const std::string line = fmt::format(
      "image {}x{}; centre {:.3g} px, worst sample {:.3g} px; corners' "
      "noise {:.3g} px (from the residuals)",
      image_width, image_height, map.at_centre_px, map.MaxPx(),
      map.observed_pixel_sigma);
  Text(&canvas, line, {left, 44}, 0.42, cv::Scalar(60, 60, 60));
  cv::Mat1b ramp(height, bar_width);
  for (int v = 0; v < height; ++v) {
    ramp.row(v).setTo(255 - v * 255 / std::max(height - 1, 1));
  }
  cv::Mat bar;
  cv::applyColorMap(ramp, bar, cv::COLORMAP_VIRIDIS);
  const int bar_left = left + width + 10;
  bar.copyTo(canvas(cv::Rect(bar_left, top, bar_width, height)));
  const double tick = 2.5 * step;
  for (int k = 0; k * tick <= colour_max_px * (1.0 + 1e-9); ++k) {
    const double value = k * tick;
    const int v = top + static_cast<int>(std::lround(
                            (1.0 - value / colour_max_px) * (height - 1)));
    cv::line(canvas, {bar_left + bar_width, v}, {bar_left + bar_width + 4, v},
             cv::Scalar(0, 0, 0));
    Text(&canvas, Format(value) + (value == 0.0 ? " px" : ""),
         {bar_left + bar_width + 6, v + 4}, 0.38, cv::Scalar(0, 0, 0));
  }
  return canvas;
}

}  // namespace uw
