#include "calib/aprilgrid_detector.h"

#include <cstdio>
#include <filesystem>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

// The 6x6 grids of the EuRoC and TUM-VI calibration frames (Kalibr's
// april_6x6: 8.8 cm tags, gap 0.3); aprilgrid-rs expects 36 tags in each.
// On the oblique TUM-VI views grid completion finds what libapriltag
// misses: r45, top_right, right and top reach 36 (top's last, the grid's
// corner at the image's edge, only by the shifted tries).
TEST(DetectAprilGrid, FindsTheTagsOfRealKalibrGrids) {
  const fs::path dir = fs::path(UW_REALDATA_DIR) / "aprilgrid_samples" /
                       "powei-lin_aprilgrid-rs_tests";
  ASSERT_TRUE(fs::is_directory(dir))
      << dir << " is missing: the tests read ../shared/realdata";
  const CalibrationBoard board = ParseBoard("aprilgrid:6x6:0.088:0.3");
  struct Case {
    const char* image;
    int at_least;  // asserted
  };
  for (const Case& c : {Case{"EuRoC.png", 36}, Case{"TUM_VI.png", 36},
                        Case{"1520525725372653511.png", 36},
                        Case{"r45.png", 36}, Case{"top_right.png", 36},
                        Case{"top.png", 36}, Case{"right.png", 36}}) {
    const cv::Mat image =
        cv::imread((dir / c.image).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << c.image;
    int tags = 0;
    const BoardObservation observation =
        DetectAprilGrid(image, board, c.image, AprilGridOptions(), &tags);
    std::printf(
        "[ figures ] %s: %d of 36 tags, %d of their %d corners kept "
        "after refinement\n",
        c.image, tags, observation.NumFoundCorners(), 4 * tags);
    EXPECT_GE(tags, c.at_least) << c.image;
    // Corners that cornerSubPix moves too far are dropped, as Kalibr
    // drops them (1 of 144 on EuRoC, 14 on the dimmest TUM-VI frame).
    if (tags > 0) {
      EXPECT_GE(observation.NumFoundCorners(), 0.85 * 4 * tags) << c.image;
    }
  }
}

TEST(DetectAprilGrid, NoGridAndBadInput) {
  const CalibrationBoard board = ParseBoard("aprilgrid:6x6:0.088:0.3");
  const cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(
      DetectAprilGrid(flat, board, "flat", AprilGridOptions()).Found());
  EXPECT_THROW(DetectAprilGrid(flat, ParseBoard("chessboard:9x6:0.02"), "x",
                               AprilGridOptions()),
               Error);
  EXPECT_THROW(DetectAprilGrid(cv::Mat(), board, "x", AprilGridOptions()),
               Error);
}

}  // namespace
}  // namespace uw
