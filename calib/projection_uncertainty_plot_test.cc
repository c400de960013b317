#include "calib/projection_uncertainty_plot.h"

#include <gtest/gtest.h>

#include "common/util/error.h"

namespace uw {
namespace {

// A map that grows with the distance from the image's centre: 0.1 px
// there, 3.1 px at the corners.
ProjectionUncertaintyMap RadialMap(int width, int height) {
  ProjectionUncertaintyMap map;
  const int columns = 60;
  const int rows = 40;
  for (int j = 0; j < columns; ++j) {
    map.x_px.push_back(j * (width - 1.0) / (columns - 1));
  }
  for (int i = 0; i < rows; ++i) {
    map.y_px.push_back(i * (height - 1.0) / (rows - 1));
  }
  map.stdev_px.resize(rows, columns);
  const double cx = (width - 1) / 2.0;
  const double cy = (height - 1) / 2.0;
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < columns; ++j) {
      const double r2 = ((map.x_px[j] - cx) * (map.x_px[j] - cx) +
                         (map.y_px[i] - cy) * (map.y_px[i] - cy)) /
                        (cx * cx + cy * cy);
      map.stdev_px(i, j) = 0.1 + 3.0 * r2;
    }
  }
  map.at_centre_px = 0.1;
  map.observed_pixel_sigma = 0.2;
  return map;
}

TEST(RenderProjectionUncertainty, HeatMapWithContoursAndColourBar) {
  const cv::Mat plot = RenderProjectionUncertainty(
      RadialMap(1024, 768), 1024, 768, "Projection uncertainty");
  ASSERT_EQ(plot.type(), CV_8UC3);
  EXPECT_GT(plot.cols, 900);
  EXPECT_GT(plot.rows, 675);
  // The image area starts at (12, 58) and is 900 x 675: viridis is dark
  // violet at 0 px and yellow from 3 px on.
  const cv::Vec3b centre = plot.at<cv::Vec3b>(58 + 337, 12 + 450);
  const cv::Vec3b corner = plot.at<cv::Vec3b>(58 + 3, 12 + 3);
  EXPECT_GT(centre[0], centre[1]);  // blue over green
  EXPECT_GT(corner[2], 200);        // red and green high: yellow
  EXPECT_GT(corner[1], 200);
  EXPECT_LT(corner[0], 100);
  // Contours: white lines cross the row through the centre.
  int white = 0;
  for (int u = 12; u < 12 + 900; ++u) {
    const cv::Vec3b pixel = plot.at<cv::Vec3b>(58 + 337, u);
    white += pixel[0] > 230 && pixel[1] > 230 && pixel[2] > 230;
  }
  EXPECT_GE(white, 10);
}

TEST(RenderProjectionUncertainty, RefusesAMapWithoutGrid) {
  EXPECT_THROW(RenderProjectionUncertainty(ProjectionUncertaintyMap(), 640, 480,
                                           "empty"),
               Error);
  EXPECT_THROW(
      RenderProjectionUncertainty(RadialMap(640, 480), 640, 480, "x", 0.0),
      Error);
}

}  // namespace
}  // namespace uw
