#include "common/util/plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace uw {
namespace {

// Series land where their values say: a horizontal line at the top of the
// data is drawn above one at the bottom, in the requested colours.
TEST(Plot, DrawsSeriesWhereTheirValuesAre) {
  Plot plot("title", "x", "y", 400, 300);
  plot.Line({0.0, 1.0}, {10.0, 10.0}, cv::Scalar(255, 0, 0));
  plot.Line({0.0, 1.0}, {0.0, 0.0}, cv::Scalar(0, 0, 255));
  const cv::Mat image = plot.Render();
  ASSERT_EQ(image.rows, 300);
  ASSERT_EQ(image.cols, 400);
  int blue_row = -1;
  int red_row = -1;
  for (int r = 0; r < image.rows; ++r) {
    const cv::Vec3b pixel = image.at<cv::Vec3b>(r, 250);
    if (pixel == cv::Vec3b(255, 0, 0) && blue_row < 0) blue_row = r;
    if (pixel == cv::Vec3b(0, 0, 255) && red_row < 0) red_row = r;
  }
  ASSERT_GE(blue_row, 0);
  ASSERT_GE(red_row, 0);
  EXPECT_LT(blue_row, red_row);
}

// Grid lines at nice values: data from 0 to 10 (padded to -0.5 ... 10.5)
// get lines at 0, 2, ..., 10, not at fifths of the padded range.
TEST(Plot, GridLinesAreAtNiceValues) {
  Plot plot("g", "x", "y", 420, 300);
  plot.Points({0.0, 10.0}, {0.0, 10.0}, cv::Scalar(0, 0, 255));
  const cv::Mat image = plot.Render();
  const cv::Vec3b grey(200, 200, 200);
  // A row at y = 5, between horizontal grid lines and away from the points.
  const int row = 50 + (300 - 50 - 60) / 2;
  std::vector<int> columns;
  for (int c = 91; c < 420 - 30; ++c) {
    if (image.at<cv::Vec3b>(row, c) == grey) columns.push_back(c);
  }
  // plot width 300 px over 11 units: x = 0, 2, ..., 10 at 90 + (x + 0.5)
  // * 300 / 11.
  std::vector<int> expected;
  for (int x = 0; x <= 10; x += 2) {
    expected.push_back(90 +
                       static_cast<int>(std::lround((x + 0.5) * 300.0 / 11.0)));
  }
  EXPECT_EQ(columns, expected);
}

TEST(Plot, HistogramBarsAreAsTallAsTheirCounts) {
  Plot plot("h", "x", "n", 400, 300);
  // Bin 0 holds three values, bin 1 one.
  plot.Histogram({0.0, 0.1, 0.2, 1.0}, 2, cv::Scalar(0, 255, 0));
  const cv::Mat image = plot.Render();
  const auto height = [&](int column) {
    int count = 0;
    for (int r = 0; r < image.rows; ++r) {
      if (image.at<cv::Vec3b>(r, column) == cv::Vec3b(0, 255, 0)) ++count;
    }
    return count;
  };
  const int tall = height(90 + 70);
  const int short_bar = height(90 + 230);
  EXPECT_GT(short_bar, 0);
  EXPECT_NEAR(static_cast<double>(tall) / short_bar, 3.0, 0.15);
}

// Bars stand on 0, as tall as their values, centred on their x and as wide
// as asked: a gap between bars 1 apart and 0.5 wide.
TEST(Plot, BarsAreCentredAndAsTallAsTheirValues) {
  Plot plot("b", "x", "y", 400, 300);
  plot.Bars({0.0, 1.0}, {2.0, 1.0}, 0.5, cv::Scalar(0, 255, 0));
  const cv::Mat image = plot.Render();
  const cv::Vec3b green(0, 255, 0);
  std::vector<int> heights(image.cols, 0);
  for (int c = 0; c < image.cols; ++c) {
    for (int r = 0; r < image.rows; ++r) {
      heights[c] += image.at<cv::Vec3b>(r, c) == green;
    }
  }
  // x in [-0.25, 1.25] padded by 5 %: the plot's 280 px span 1.65 units.
  const auto column = [](double x) {
    return 90 + static_cast<int>(std::lround((x + 0.325) / 1.65 * 280));
  };
  EXPECT_GT(heights[column(0.0)], 0);
  EXPECT_NEAR(static_cast<double>(heights[column(0.0)]) / heights[column(1.0)],
              2.0, 0.05);
  EXPECT_EQ(heights[column(0.5)], 0);
  EXPECT_EQ(heights[column(-0.3)], 0);
  EXPECT_GT(heights[column(-0.2)], 0);
}

}  // namespace
}  // namespace uw
