#include "calib/board_laser_calibration.h"

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "calib/calibration_testing.h"
#include "calib/mission_scene_testing.h"
#include "common/util/error_testing.h"
#include "sim/laser.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// Set-up C's lasers on the laser board at `num_distances`, as PNG files,
// and an image of another size.
std::vector<std::string> WriteSession(const Camera& camera,
                                      const LaserSetup& truth,
                                      int num_distances, const fs::path& dir) {
  std::vector<std::string> names;
  const std::vector<testing_calibration::LaserBoardView> views =
      testing_calibration::RenderLaserBoardViews(camera, truth, num_distances,
                                                 4);
  for (size_t v = 0; v < views.size(); ++v) {
    names.push_back("board" + std::to_string(v) + ".png");
    EXPECT_TRUE(cv::imwrite((dir / names.back()).string(), views[v].bgr));
  }
  EXPECT_TRUE(cv::imwrite((dir / "small.png").string(),
                          cv::Mat(10, 20, CV_8UC3, cv::Scalar::all(0))));
  return names;
}

TEST(CalibrateLasersFromBoardImages, FitsEveryLaserOfTheImages) {
  const fs::path dir = testing::FreshTestDir("uw_board_laser_calibration");
  const Camera camera = testing_calibration::TrueCamera();
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const std::vector<std::string> names = WriteSession(camera, truth, 6, dir);
  BoardLaserCalibrationOptions options;
  options.num_lasers = static_cast<int>(truth.lasers.size());
  options.setup_name = "bench";
  options.spots.colour = Eigen::Vector3d(1.0, 0.0, 0.0);
  options.Check();
  std::vector<std::string> seen;
  const BoardLaserCalibration result = CalibrateLasersFromBoardImages(
      camera, testing_calibration::LaserBoard(), dir.string(), names, options,
      [&](const std::string& image, bool board_found, size_t num_spots) {
        seen.push_back(image);
        EXPECT_TRUE(board_found) << image;
        EXPECT_EQ(num_spots, truth.lasers.size()) << image;
      });
  EXPECT_EQ(seen, names);
  EXPECT_EQ(result.num_images_with_board, 6);
  EXPECT_EQ(result.setup.name, "bench");
  ASSERT_EQ(result.setup.lasers.size(), truth.lasers.size());
  ASSERT_EQ(result.fits.size(), truth.lasers.size());
  for (size_t l = 0; l < result.fits.size(); ++l) {
    const Laser& laser = result.setup.lasers[l];
    EXPECT_EQ(laser.name, "L" + std::to_string(l));
    EXPECT_EQ(laser.colour, options.spots.colour);
    EXPECT_EQ(result.fits[l].points_in_cam.size(), 6u);
    double nearest_deg = 180.0;
    for (const Laser& true_laser : truth.lasers) {
      nearest_deg = std::min(
          nearest_deg, testing_mission::AngleDeg(laser.direction_in_cam,
                                                 true_laser.direction_in_cam));
    }
    EXPECT_LT(nearest_deg, 0.1) << laser.name;
  }
}

TEST(CalibrateLasersFromBoardImages, RefusesTooFewBoardsAndForeignImages) {
  const fs::path dir = testing::FreshTestDir("uw_board_laser_calibration");
  const Camera camera = testing_calibration::TrueCamera();
  const LaserSetup truth = sim::TrueLaserSetup(sim::LaserOptions());
  const std::vector<std::string> names = WriteSession(camera, truth, 2, dir);
  BoardLaserCalibrationOptions options;
  options.num_lasers = 4;
  ExpectErrorContaining(
      [&] {
        CalibrateLasersFromBoardImages(
            camera, testing_calibration::LaserBoard(), dir.string(),
            {names[0], names[1]}, options);
      },
      ": the board was found in 2 of 2 images; at least 3 distances are "
      "needed; nothing written");
  ExpectErrorContaining(
      [&] {
        CalibrateLasersFromBoardImages(camera,
                                       testing_calibration::LaserBoard(),
                                       dir.string(), {"small.png"}, options);
      },
      "small.png: 20x10, but the camera model is 1024x768");
  ExpectErrorContaining(
      [&] {
        CalibrateLasersFromBoardImages(camera,
                                       testing_calibration::LaserBoard(),
                                       dir.string(), {"none.png"}, options);
      },
      "none.png: cannot read the image");
}

TEST(DescribeLaserLineFit, DepthsOriginDirectionAndTheirSigma) {
  LaserLineFit fit;
  fit.laser.name = "L2";
  fit.laser.origin_in_cam = Eigen::Vector3d(0.1, -0.12346, 0.0);
  fit.laser.origin_cov = Eigen::Matrix3d::Identity() * 1e-8;
  fit.laser.direction_in_cam = Eigen::Vector3d(0.0, 0.6, 0.8);
  fit.laser.direction_cov = Eigen::Matrix3d::Zero();
  fit.points_in_cam = {{0.0, 0.0, 0.6}, {0.0, 0.0, 3.614}};
  fit.rms_distance_m = 0.00026;
  EXPECT_EQ(DescribeLaserLineFit(fit),
            "laser L2: 2 spots from 0.60 to 3.61 m; origin (0.1000, -0.1235) "
            "m (sigma 0.17 mm), direction (0.00000, 0.60000, 0.80000) "
            "(sigma 0.0000 deg); line RMS 0.26 mm");
}

}  // namespace
}  // namespace uw
