// Plots for the reports (PNG through OpenCV, no plotting dependency): one
// pair of linear axes, autoscaled to everything drawn, with series of
// lines, points, error bars and histogram bars, and a legend. Enough for a
// scientist to read a result at a glance; the numbers are in the JSON/CSV.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace uw {

// Encodes `image` as PNG and writes it atomically; throws uw::Error naming
// the path.
void WritePngAtomically(const cv::Mat& image,
                        const std::filesystem::path& path);

class Plot {
 public:
  // BGR colours of the series, in order of use.
  static cv::Scalar Colour(int index);

  Plot(std::string title, std::string x_label, std::string y_label,
       int width = 900, int height = 520);

  void Line(const std::vector<double>& x, const std::vector<double>& y,
            const cv::Scalar& colour, const std::string& label = "");
  void Points(const std::vector<double>& x, const std::vector<double>& y,
              const cv::Scalar& colour, const std::string& label = "");
  // Vertical bars from low to high at each x.
  void ErrorBars(const std::vector<double>& x, const std::vector<double>& low,
                 const std::vector<double>& high, const cv::Scalar& colour,
                 const std::string& label = "");
  // Bars from 0 to heights[i], centred on x[i] and `width` wide (x units).
  void Bars(const std::vector<double>& x, const std::vector<double>& heights,
            double width, const cv::Scalar& colour,
            const std::string& label = "");
  // A histogram of `values` in `num_bins` bins over their range.
  void Histogram(const std::vector<double>& values, int num_bins,
                 const cv::Scalar& colour, const std::string& label = "");
  void HorizontalLine(double y, const cv::Scalar& colour,
                      const std::string& label = "");
  void VerticalLine(double x, const cv::Scalar& colour,
                    const std::string& label = "");

  cv::Mat Render() const;
  // Atomic write; throws uw::Error naming the path.
  void WritePng(const std::filesystem::path& path) const;

 private:
  enum class Kind { kLine, kPoints, kErrorBars, kBars, kHLine, kVLine };
  struct Series {
    Kind kind;
    std::vector<double> x, y, y2;
    cv::Scalar colour;
    std::string label;
  };
  void Add(Series series);

  std::string title_, x_label_, y_label_;
  int width_, height_;
  std::vector<Series> series_;
};

}  // namespace uw
