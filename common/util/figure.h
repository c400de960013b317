// Figures for the reports, drawn by matplotlib (scripts/uwplot.py, embedded
// in the programs and run by /usr/bin/python3): one pair of axes with
// series of lines, points, error bars, bars and histograms, a legend, ticks
// at multiples of 1, 2 or 5 x 10^k without offsets, and item axes that name
// their items (image names). Every figure is written as PNG (for the HTML
// reports) and SVG (for a paper: text kept as text). The numbers drawn are
// those of the CSV/JSON written beside them.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/util/file.h"

namespace uw {

class Figure {
 public:
  // matplotlib's colour cycle ("C0" ... "C9"), so figures match each other.
  static std::string Colour(int index);

  Figure(std::string title, std::string x_label, std::string y_label,
         double width_in = 10.0, double height_in = 5.0);

  void Line(const std::vector<double>& x, const std::vector<double>& y,
            const std::string& colour, const std::string& label = "");
  void Points(const std::vector<double>& x, const std::vector<double>& y,
              const std::string& colour, const std::string& label = "");
  // Vertical bars from low to high at each x.
  void ErrorBars(const std::vector<double>& x, const std::vector<double>& low,
                 const std::vector<double>& high, const std::string& colour,
                 const std::string& label = "");
  // Bars from 0 to heights[i], centred on x[i] and `width` wide (x units).
  void Bars(const std::vector<double>& x, const std::vector<double>& heights,
            double width, const std::string& colour,
            const std::string& label = "");
  // A histogram of the finite `values` in `num_bins` bins over their range.
  void Histogram(const std::vector<double>& values, int num_bins,
                 const std::string& colour, const std::string& label = "");
  void HorizontalLine(double y, const std::string& colour,
                      const std::string& label = "");
  void VerticalLine(double x, const std::string& colour,
                    const std::string& label = "");

  // x = 0, 1, ... are these items (image names): the axis is labelled with
  // them (at most 60 shown, evenly thinned) instead of numbers.
  void ItemAxis(std::vector<std::string> names);
  void LogX();
  void LogY();
  // One unit is as long on x as on y (plan views).
  void EqualAspect();

  // What uwplot.py draws, without the output paths.
  const nlohmann::json& Spec() const { return spec_; }

 private:
  void Add(nlohmann::json series);

  nlohmann::json spec_;
};

// One figure's files, as drawn.
struct FigureFiles {
  std::string png;
  std::string svg;
};

// Draws the figures in one run of /usr/bin/python3 (in a temporary folder
// that is removed afterwards). Throws uw::Error when python3 or matplotlib
// is missing (naming the Debian package) or a figure cannot be drawn
// (quoting the script's message).
std::vector<FigureFiles> DrawFigures(const std::vector<Figure>& figures);

// The drawn figures as files to write with others in one atomic set
// (file.h): drawn[i] as png_paths[i] and the same path with ".svg". The
// writers point into `drawn`, which must outlive them.
std::vector<PendingFile> FigureFileSet(
    const std::vector<FigureFiles>& drawn,
    const std::vector<std::filesystem::path>& png_paths);

// Draws each figure as png_paths[i] and the same path with ".svg", and
// writes all of them atomically as one set.
void WriteFigures(const std::vector<Figure>& figures,
                  const std::vector<std::filesystem::path>& png_paths);

}  // namespace uw
