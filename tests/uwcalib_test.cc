// uwcalib detect + calibrate on OpenCV's real chessboard images, checked
// with mrcal's own reader; bad input refused with nothing written.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "calib/corners_vnl.h"
#include "calib/mrcal_calibration.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
using testing::FreshTestDir;
using testing::Quoted;
using testing::RunProcess;

const fs::path kUwcalib = fs::path(UW_BIN_DIR) / "uwcalib";
const fs::path kImages =
    fs::path(UW_REALDATA_DIR) / "opencv_chessboard_stereo_640x480";

TEST(Uwcalib, DetectAndCalibrateTheLeftCamera) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  {
    std::ofstream list(dir / "left.txt");
    for (const char* n : {"01", "02", "03", "04", "05", "06", "07", "08", "09",
                          "11", "12", "13", "14"}) {
      list << "left" << n << ".jpg\n";
    }
  }
  const auto detect = RunProcess(
      kUwcalib.string() + " detect --board chessboard:9x6:0.025 --images " +
          Quoted(kImages) + " --image_list_path " + Quoted(dir / "left.txt") +
          " --out " + Quoted(dir / "corners.vnl"),
      true);
  ASSERT_EQ(detect.exit_code, 0) << detect.output;
  EXPECT_NE(detect.output.find("board found in 13 of 13 images"),
            std::string::npos)
      << detect.output;
  const CornersVnl corners = ReadCornersVnl((dir / "corners.vnl").string(), 54);
  EXPECT_EQ(corners.observations.size(), 13u);

  const auto calibrate = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "corners.vnl") +
          " --lens_model LENSMODEL_OPENCV5 --focal 530 --imagersize 640,480 "
          "--out " +
          Quoted(dir / "cal"),
      true);
  ASSERT_EQ(calibrate.exit_code, 0) << calibrate.output;
  const MrcalCameraModel model =
      ReadCameraModel((dir / "cal" / "camera-0.cameramodel").string());
  EXPECT_EQ(model.lens_model, "LENSMODEL_OPENCV5");
  EXPECT_NEAR(model.intrinsics[0], 533.1, 1.0);  // OpenCV: 531.9
  EXPECT_TRUE(fs::exists(dir / "cal" / "calibration.json"));
}

TEST(Uwcalib, BadInputIsRefusedAndNothingIsWritten) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  // Images without the board (the board asked for is not the one shown).
  auto result = RunProcess(
      kUwcalib.string() + " detect --board chessboard:7x7:0.025 --images " +
          Quoted(kImages) + " --out " + Quoted(dir / "corners.vnl"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("no image shows the whole board"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "corners.vnl"));

  // A malformed corners file.
  std::ofstream(dir / "bad.vnl") << "# filename x y level\na.jpg 1 2 0\n";
  result = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "bad.vnl") + " --focal 530 --imagersize 640,480 --out " +
          Quoted(dir / "cal"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("bad.vnl:2: image a.jpg has 1 rows"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "cal"));

  // Too few views for the lens model: two boards.
  std::ofstream two(dir / "two.vnl");
  for (const char* image : {"a.jpg", "b.jpg"}) {
    for (int j = 0; j < 6; ++j) {
      for (int i = 0; i < 9; ++i) {
        two << image << " " << 100 + 20 * i + j << " " << 100 + 20 * j
            << " 0\n";
      }
    }
  }
  two.close();
  result = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "two.vnl") + " --focal 530 --imagersize 640,480 --out " +
          Quoted(dir / "cal"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("2 board views"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "cal"));
}

}  // namespace
}  // namespace uw
