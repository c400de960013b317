#include "calib/calibration_report.h"

#include <gtest/gtest.h>

#include "calib/calibration_testing.h"
#include "sim/board_images.h"

namespace uw {
namespace {

using testing_calibration::Options;
using testing_calibration::TrueCamera;

// One camera calibrated from noisy views, and the same camera again as a
// rig's second, 12 cm to the side: the lines uwcalib calibrate prints.
TEST(DescribeRigCalibration, ViewsOutliersBaselineAndCentreUncertainty) {
  const Camera camera = TrueCamera();
  const CalibrationBoard board = ParseBoard("chessboard:10x7:0.04");
  RigCameraViews views;
  views.views = testing_calibration::ViewsWithNoise(
      camera, board,
      sim::RandomBoardPoses(camera, board, 20, 0.4, 0.9, 45.0, 5), 0.3, 6);
  for (size_t v = 0; v < views.views.size(); ++v) {
    views.frames.push_back(static_cast<int>(v));
  }
  MrcalRigCalibration result = CalibrateRigWithMrcal(
      {views}, board, Options("LENSMODEL_OPENCV4", 800.0, 1024, 768));
  result.cameras.push_back(result.cameras[0]);
  Rigid3d right_from_left;
  right_from_left.translation = Eigen::Vector3d(-0.12, 0.0, 0.0);
  result.cam_from_rig.push_back(right_from_left);

  ProjectionUncertaintyOptions uncertainty;
  const std::vector<std::string> at_infinity =
      DescribeRigCalibration(result, uncertainty);
  ASSERT_EQ(at_infinity.size(), 4u);
  const std::string views_line =
      "20 views, " + std::to_string(result.cameras[0].num_outliers) +
      " outliers of " + std::to_string(result.cameras[0].num_corners_observed) +
      " corners";
  EXPECT_EQ(at_infinity[0], "camera 0: " + views_line);
  EXPECT_EQ(at_infinity[1],
            "camera 1: " + views_line + ", baseline 0.120000 m");
  EXPECT_EQ(at_infinity[2].rfind("camera 0: projection uncertainty at the "
                                 "centre 0.",
                                 0),
            0u)
      << at_infinity[2];
  EXPECT_NE(at_infinity[2].find(" px (1-sigma, worst direction), at infinity"),
            std::string::npos)
      << at_infinity[2];

  uncertainty.distance = 2.5;
  const std::vector<std::string> near =
      DescribeRigCalibration(result, uncertainty);
  ASSERT_EQ(near.size(), 4u);
  EXPECT_NE(near[3].find("camera 1: projection uncertainty at the centre "),
            std::string::npos);
  EXPECT_NE(near[3].find(" px (1-sigma, worst direction), 2.5 m out"),
            std::string::npos)
      << near[3];
}

}  // namespace
}  // namespace uw
