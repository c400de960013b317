#include "common/util/plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/util/error.h"
#include "common/util/file.h"
#include "common/util/nice_ticks.h"

namespace uw {
namespace {

constexpr int kLeft = 90;
constexpr int kRight = 30;
constexpr int kTop = 50;
constexpr int kBottom = 60;

}  // namespace

cv::Scalar Plot::Colour(int index) {
  static const cv::Scalar colours[] = {
      {180, 110, 30}, {40, 120, 230}, {60, 160, 60},  {40, 40, 200},
      {170, 90, 150}, {60, 90, 140},  {150, 150, 40}, {120, 120, 120}};
  return colours[index % 8];
}

Plot::Plot(std::string title, std::string x_label, std::string y_label,
           int width, int height)
    : title_(std::move(title)),
      x_label_(std::move(x_label)),
      y_label_(std::move(y_label)),
      width_(width),
      height_(height) {}

void Plot::Add(Series series) { series_.push_back(std::move(series)); }

void Plot::Line(const std::vector<double>& x, const std::vector<double>& y,
                const cv::Scalar& colour, const std::string& label) {
  Add({Kind::kLine, x, y, {}, colour, label});
}

void Plot::Points(const std::vector<double>& x, const std::vector<double>& y,
                  const cv::Scalar& colour, const std::string& label) {
  Add({Kind::kPoints, x, y, {}, colour, label});
}

void Plot::ErrorBars(const std::vector<double>& x,
                     const std::vector<double>& low,
                     const std::vector<double>& high, const cv::Scalar& colour,
                     const std::string& label) {
  Add({Kind::kErrorBars, x, low, high, colour, label});
}

void Plot::Bars(const std::vector<double>& x,
                const std::vector<double>& heights, double width,
                const cv::Scalar& colour, const std::string& label) {
  std::vector<double> left, right;
  for (const double centre : x) {
    left.push_back(centre - 0.5 * width);
    right.push_back(centre + 0.5 * width);
  }
  Add({Kind::kBars, left, heights, right, colour, label});
}

void Plot::Histogram(const std::vector<double>& values, int num_bins,
                     const cv::Scalar& colour, const std::string& label) {
  std::vector<double> finite;
  for (const double v : values) {
    if (std::isfinite(v)) finite.push_back(v);
  }
  if (finite.empty() || num_bins < 1) return;
  const auto [lo, hi] = std::minmax_element(finite.begin(), finite.end());
  const double low = *lo;
  const double width = std::max(*hi - *lo, 1e-300) / num_bins;
  std::vector<double> edges;
  std::vector<double> counts(num_bins, 0.0);
  for (const double v : finite) {
    const int bin = std::min(num_bins - 1, static_cast<int>((v - low) / width));
    counts[bin] += 1.0;
  }
  for (int b = 0; b < num_bins; ++b) edges.push_back(low + b * width);
  std::vector<double> right;
  for (int b = 0; b < num_bins; ++b) right.push_back(low + (b + 1) * width);
  Add({Kind::kBars, edges, counts, right, colour, label});
}

void Plot::HorizontalLine(double y, const cv::Scalar& colour,
                          const std::string& label) {
  Add({Kind::kHLine, {}, {y}, {}, colour, label});
}

void Plot::VerticalLine(double x, const cv::Scalar& colour,
                        const std::string& label) {
  Add({Kind::kVLine, {x}, {}, {}, colour, label});
}

cv::Mat Plot::Render() const {
  cv::Mat image(height_, width_, CV_8UC3, cv::Scalar(255, 255, 255));
  double x_lo = std::numeric_limits<double>::infinity();
  double x_hi = -x_lo;
  double y_lo = x_lo;
  double y_hi = -x_lo;
  const auto extend = [](double v, double* lo, double* hi) {
    if (!std::isfinite(v)) return;
    *lo = std::min(*lo, v);
    *hi = std::max(*hi, v);
  };
  for (const Series& s : series_) {
    for (const double v : s.x) extend(v, &x_lo, &x_hi);
    for (const double v : s.y) extend(v, &y_lo, &y_hi);
    for (const double v : s.y2) {
      extend(v, s.kind == Kind::kBars ? &x_lo : &y_lo,
             s.kind == Kind::kBars ? &x_hi : &y_hi);
    }
    if (s.kind == Kind::kBars) extend(0.0, &y_lo, &y_hi);
  }
  if (!std::isfinite(x_lo)) x_lo = 0.0, x_hi = 1.0;
  if (!std::isfinite(y_lo)) y_lo = 0.0, y_hi = 1.0;
  const auto pad = [](double* lo, double* hi) {
    const double span = *hi - *lo;
    const double margin =
        span > 0.0 ? 0.05 * span : 0.5 * std::max(1e-12, std::abs(*lo));
    *lo -= margin;
    *hi += margin;
  };
  pad(&x_lo, &x_hi);
  pad(&y_lo, &y_hi);
  const int plot_w = width_ - kLeft - kRight;
  const int plot_h = height_ - kTop - kBottom;
  const auto to_px = [&](double x, double y) {
    return cv::Point(
        kLeft +
            static_cast<int>(std::lround((x - x_lo) / (x_hi - x_lo) * plot_w)),
        kTop + plot_h -
            static_cast<int>(std::lround((y - y_lo) / (y_hi - y_lo) * plot_h)));
  };
  const cv::Scalar black(0, 0, 0);
  const cv::Scalar grey(200, 200, 200);
  const auto text = [&](const std::string& s, cv::Point at,
                        double size = 0.45) {
    cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, size, black, 1,
                cv::LINE_AA);
  };
  // Grid lines and labels at nice values, not at fifths of the padded
  // range (which read -0.5075, 2.28375).
  constexpr int kMaxTicks = 6;
  const Ticks x_ticks = NiceTicks(x_lo, x_hi, kMaxTicks);
  for (const double x : x_ticks.values) {
    cv::line(image, to_px(x, y_lo), to_px(x, y_hi), grey, 1);
    text(TickLabel(x, x_ticks.step), to_px(x, y_lo) + cv::Point(-12, 18), 0.4);
  }
  const Ticks y_ticks = NiceTicks(y_lo, y_hi, kMaxTicks);
  for (const double y : y_ticks.values) {
    cv::line(image, to_px(x_lo, y), to_px(x_hi, y), grey, 1);
    text(TickLabel(y, y_ticks.step), to_px(x_lo, y) + cv::Point(-kLeft + 5, 4),
         0.4);
  }
  cv::rectangle(image, {kLeft, kTop}, {kLeft + plot_w, kTop + plot_h}, black);
  for (const Series& s : series_) {
    switch (s.kind) {
      case Kind::kLine:
        for (size_t i = 0; i + 1 < s.x.size(); ++i) {
          if (!std::isfinite(s.y[i]) || !std::isfinite(s.y[i + 1])) continue;
          cv::line(image, to_px(s.x[i], s.y[i]), to_px(s.x[i + 1], s.y[i + 1]),
                   s.colour, 2, cv::LINE_AA);
        }
        break;
      case Kind::kPoints:
        for (size_t i = 0; i < s.x.size(); ++i) {
          if (!std::isfinite(s.y[i])) continue;
          cv::circle(image, to_px(s.x[i], s.y[i]), 3, s.colour, cv::FILLED,
                     cv::LINE_AA);
        }
        break;
      case Kind::kErrorBars:
        for (size_t i = 0; i < s.x.size(); ++i) {
          if (!std::isfinite(s.y[i]) || !std::isfinite(s.y2[i])) continue;
          const cv::Point a = to_px(s.x[i], s.y[i]);
          const cv::Point b = to_px(s.x[i], s.y2[i]);
          cv::line(image, a, b, s.colour, 2, cv::LINE_AA);
          cv::line(image, a - cv::Point(4, 0), a + cv::Point(4, 0), s.colour,
                   2);
          cv::line(image, b - cv::Point(4, 0), b + cv::Point(4, 0), s.colour,
                   2);
        }
        break;
      case Kind::kBars:
        for (size_t i = 0; i < s.x.size(); ++i) {
          cv::rectangle(image, to_px(s.x[i], 0.0), to_px(s.y2[i], s.y[i]),
                        s.colour, cv::FILLED);
        }
        break;
      case Kind::kHLine:
        cv::line(image, to_px(x_lo, s.y[0]), to_px(x_hi, s.y[0]), s.colour, 1,
                 cv::LINE_AA);
        break;
      case Kind::kVLine:
        cv::line(image, to_px(s.x[0], y_lo), to_px(s.x[0], y_hi), s.colour, 1,
                 cv::LINE_AA);
        break;
    }
  }
  text(title_, {kLeft, 30}, 0.6);
  text(x_label_, {kLeft + plot_w / 2 - 60, height_ - 15});
  text(y_label_, {5, kTop - 10});
  int legend_y = kTop + 20;
  for (const Series& s : series_) {
    if (s.label.empty()) continue;
    const cv::Point at(kLeft + plot_w - 230, legend_y);
    cv::rectangle(image, at + cv::Point(0, -9), at + cv::Point(14, 1), s.colour,
                  cv::FILLED);
    text(s.label, at + cv::Point(20, 0), 0.42);
    legend_y += 18;
  }
  return image;
}

void WritePngAtomically(const cv::Mat& image,
                        const std::filesystem::path& path) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes)) {
    throw ErrorAt(path.string(), ": cannot encode the image as PNG");
  }
  WriteFilesAtomically({{path,
                         [&](std::ostream& out) {
                           out.write(
                               reinterpret_cast<const char*>(bytes.data()),
                               static_cast<std::streamsize>(bytes.size()));
                         }}},
                       true);
}

void Plot::WritePng(const std::filesystem::path& path) const {
  WritePngAtomically(Render(), path);
}

}  // namespace uw
