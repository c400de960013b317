// The parts of `uwcalib lasers`: the board's pose, the spots of a colour,
// and the lasers told apart and fitted, on rendered laser board images.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "calib/board_pose.h"
#include "calib/calibration_testing.h"
#include "calib/chessboard_detector.h"
#include "calib/colour_spots.h"
#include "calib/laser_line_fit.h"
#include "calib/mission_scene_testing.h"
#include "common/util/error.h"
#include "sim/laser.h"

namespace uw {
namespace {

using testing_calibration::LaserBoard;
using testing_calibration::LaserBoardView;
using testing_calibration::RenderLaserBoardViews;
using testing_calibration::TrueCamera;
using testing_mission::AngleDeg;

// Acceptance (issue 6, 5) through the images: set-up C's four lasers on a
// board at 12 distances; poses from detected corners, spots found by their
// colour, the lasers told apart: directions within 0.05 deg, origins within
// 1 mm.
TEST(BoardLasers, RecoversSetupCFromRenderedImages) {
  const Camera camera = TrueCamera();
  const CalibrationBoard board = LaserBoard();
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const std::vector<LaserBoardView> views =
      RenderLaserBoardViews(camera, truth, 12, 5);
  std::vector<LaserBoardSpot> spots;
  double worst_spot_px = 0.0;
  double worst_rotation_deg = 0.0;
  double worst_translation_mm = 0.0;
  for (size_t v = 0; v < views.size(); ++v) {
    cv::Mat grey;
    cv::cvtColor(views[v].bgr, grey, cv::COLOR_BGR2GRAY);
    const std::string name = "board" + std::to_string(v);
    const std::optional<Rigid3d> pose =
        EstimateBoardPose(camera, board, DetectChessboard(grey, board, name));
    ASSERT_TRUE(pose.has_value()) << name;
    worst_rotation_deg = std::max(
        worst_rotation_deg,
        pose->rotation.angularDistance(views[v].cam_from_board.rotation) *
            180.0 / M_PI);
    worst_translation_mm = std::max(
        worst_translation_mm,
        1000.0 *
            (pose->translation - views[v].cam_from_board.translation).norm());
    const std::vector<Eigen::Vector2d> found =
        FindColourSpots(views[v].bgr, ColourSpotOptions());
    ASSERT_EQ(found.size(), truth.lasers.size()) << name;
    for (const Eigen::Vector2d& pixel : found) {
      double nearest = 1e9;
      for (const Eigen::Vector2d& spot : views[v].spots) {
        nearest = std::min(nearest, (pixel - spot).norm());
      }
      worst_spot_px = std::max(worst_spot_px, nearest);
      spots.push_back({name, *pose, pixel});
    }
  }
  std::printf(
      "[ figures ] 12 rendered boards: poses within %.3f deg and %.2f mm, "
      "spots within %.3f px of the truth\n",
      worst_rotation_deg, worst_translation_mm, worst_spot_px);
  // A spot across a square's edge keeps a little of the edge after the
  // background's median is taken away.
  EXPECT_LT(worst_spot_px, 0.25);
  const std::vector<LaserLineFit> fits =
      FitLaserLines(camera, spots, 4, LaserLineFitOptions());
  ASSERT_EQ(fits.size(), 4u);
  for (const LaserLineFit& fit : fits) {
    // The true laser nearest to the fitted one, by origin.
    const Laser* nearest = nullptr;
    for (const Laser& laser : truth.lasers) {
      if (nearest == nullptr ||
          (laser.origin_in_cam - fit.laser.origin_in_cam).norm() <
              (nearest->origin_in_cam - fit.laser.origin_in_cam).norm()) {
        nearest = &laser;
      }
    }
    const double angle =
        AngleDeg(fit.laser.direction_in_cam, nearest->direction_in_cam);
    const double origin_mm =
        1000.0 * (fit.laser.origin_in_cam - nearest->origin_in_cam).norm();
    std::printf(
        "[ figures ] %s (true %s): %zu spots, direction %.4f deg off, origin "
        "%.3f mm off\n",
        fit.laser.name.c_str(), nearest->name.c_str(), fit.points_in_cam.size(),
        angle, origin_mm);
    EXPECT_EQ(fit.points_in_cam.size(), 12u) << fit.laser.name;
    EXPECT_LT(angle, 0.05) << fit.laser.name;
    EXPECT_LT(origin_mm, 1.0) << fit.laser.name;
  }
  // Named around the optical axis from +x towards +y.
  for (size_t l = 1; l < fits.size(); ++l) {
    EXPECT_LT(std::atan2(fits[l - 1].laser.origin_in_cam.y(),
                         fits[l - 1].laser.origin_in_cam.x()),
              std::atan2(fits[l].laser.origin_in_cam.y(),
                         fits[l].laser.origin_in_cam.x()));
  }
}

TEST(BoardLasers, BadInputAndNoSpots) {
  const cv::Mat grey_image(480, 640, CV_8UC3, cv::Scalar(90, 90, 90));
  EXPECT_TRUE(FindColourSpots(grey_image, ColourSpotOptions()).empty());
  ColourSpotOptions grey;
  grey.colour = Eigen::Vector3d(0.5, 0.5, 0.5);
  EXPECT_THROW(FindColourSpots(grey_image, grey), Error);
  EXPECT_THROW(FindColourSpots(cv::Mat(10, 10, CV_8UC1), ColourSpotOptions()),
               Error);
  const CalibrationBoard board = LaserBoard();
  BoardObservation none;
  EXPECT_FALSE(EstimateBoardPose(TrueCamera(), board, none).has_value());
  EXPECT_THROW(FitLaserLines(TrueCamera(), {}, 0, LaserLineFitOptions()),
               Error);
}

}  // namespace
}  // namespace uw
