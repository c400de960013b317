// uwcalib detect + calibrate on OpenCV's real chessboard images, checked
// with mrcal's own reader; bad input refused with nothing written.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

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
  const nlohmann::json report =
      nlohmann::json::parse(std::ifstream(dir / "cal" / "calibration.json"));
  EXPECT_EQ(report["cameras"][0]["images"].size(), 13u);
  EXPECT_EQ(report["lens_model"], "LENSMODEL_OPENCV5");
  for (const char* plot : {"residuals.png", "residuals_per_image.png"}) {
    EXPECT_FALSE(cv::imread((dir / "cal" / plot).string()).empty()) << plot;
  }

  // The camera into a COLMAP model that stock colmap reads: its text has
  // the camera, cx and cy moved by +0.5 to COLMAP's pixel centres.
  const auto exported =
      RunProcess(kUwcalib.string() + " export --cameramodel " +
                     Quoted(dir / "cal" / "camera-0.cameramodel") +
                     " --to colmap --output_type BIN --output_path " +
                     Quoted(dir / "colmap_bin"),
                 true);
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_NE(exported.output.find("1 FULL_OPENCV 640 480 "), std::string::npos)
      << exported.output;
  fs::create_directories(dir / "colmap_txt");
  const auto converted = RunProcess(
      "colmap model_converter --input_path " + Quoted(dir / "colmap_bin") +
          " --output_path " + Quoted(dir / "colmap_txt") + " --output_type TXT",
      true);
  ASSERT_EQ(converted.exit_code, 0) << converted.output;
  std::ifstream cameras(dir / "colmap_txt" / "cameras.txt");
  std::string line;
  while (std::getline(cameras, line) && line[0] == '#') {
  }
  std::istringstream fields(line);
  std::string id, name;
  int width = 0, height = 0;
  std::vector<double> params(12);
  fields >> id >> name >> width >> height;
  for (double& param : params) fields >> param;
  EXPECT_EQ(name, "FULL_OPENCV");
  EXPECT_NEAR(params[2], model.intrinsics[2] + 0.5, 1e-9);
  EXPECT_NEAR(params[3], model.intrinsics[3] + 0.5, 1e-9);
  EXPECT_NEAR(params[8], model.intrinsics[8], 1e-12);  // k3
  EXPECT_EQ(params[9], 0.0);                           // OPENCV5: no k4

  const auto yaml =
      RunProcess(kUwcalib.string() + " export --cameramodel " +
                     Quoted(dir / "cal" / "camera-0.cameramodel") +
                     " --to opencv-yaml --out " + Quoted(dir / "camera.yaml"),
                 true);
  ASSERT_EQ(yaml.exit_code, 0) << yaml.output;
  EXPECT_TRUE(fs::exists(dir / "camera.yaml"));
}

// Both cameras of the stereo pair from one corners.vnl, split by globs and
// paired by the numbers in their names: the baseline as the library's
// (CalibrateRigWithMrcal.*: 3.3267 squares, within 0.02 % of OpenCV's
// stereoCalibrate), here in metres for 25 mm squares.
TEST(Uwcalib, CalibratesTheStereoPair) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  auto result = RunProcess(
      kUwcalib.string() + " detect --board chessboard:9x6:0.025 --images " +
          Quoted(kImages) + " --out " + Quoted(dir / "corners.vnl"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("board found in 26 of 26 images"),
            std::string::npos)
      << result.output;
  result = RunProcess(
      kUwcalib.string() + " calibrate --board chessboard:9x6:0.025 --corners " +
          Quoted(dir / "corners.vnl") +
          " --cameras 'left*.jpg,right*.jpg' --lens_model LENSMODEL_OPENCV5"
          " --focal 530 --imagersize 640,480 --out " +
          Quoted(dir / "stereo"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const MrcalCameraModel left =
      ReadCameraModel((dir / "stereo" / "camera-0.cameramodel").string());
  const MrcalCameraModel right =
      ReadCameraModel((dir / "stereo" / "camera-1.cameramodel").string());
  EXPECT_EQ(left.rt_cam_ref.norm(), 0.0);
  EXPECT_NEAR(right.rt_cam_ref.tail<3>().norm(), 3.3267 * 0.025, 0.0005);
}

// Kalibr AprilGrids into corners.vnl (Kalibr's corner order, '-' for the
// corners of missing tags), which calibrate reads (two frames of two
// cameras are too few, and it says so).
TEST(Uwcalib, DetectsAprilGridsIntoCornersVnl) {
  const fs::path dir = FreshTestDir("uw_uwcalib_test");
  std::ofstream(dir / "grids.txt") << "EuRoC.png\nTUM_VI.png\n";
  const fs::path images = fs::path(UW_REALDATA_DIR) / "aprilgrid_samples" /
                          "powei-lin_aprilgrid-rs_tests";
  auto result = RunProcess(
      kUwcalib.string() + " detect --board aprilgrid:6x6:0.088:0.3 --images " +
          Quoted(images) + " --image_list_path " + Quoted(dir / "grids.txt") +
          " --out " + Quoted(dir / "corners.vnl"),
      true);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const CornersVnl corners =
      ReadCornersVnl((dir / "corners.vnl").string(), 144);
  ASSERT_EQ(corners.observations.size(), 2u);
  EXPECT_GE(corners.observations[0].NumFoundCorners(), 140);
  result = RunProcess(
      kUwcalib.string() +
          " calibrate --board aprilgrid:6x6:0.088:0.3 --corners " +
          Quoted(dir / "corners.vnl") +
          " --focal 460 --imagersize 752,480 --out " + Quoted(dir / "cal"),
      true);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("2 board views are too few"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "cal"));
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
