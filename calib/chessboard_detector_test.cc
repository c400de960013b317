#include "calib/chessboard_detector.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "calib/corners_vnl.h"
#include "common/util/error.h"
#include "common/util/subprocess.h"
#include "sim/board_images.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

Camera DistortedCamera() {
  Camera camera;
  camera.model_id = CameraModelId::kOpenCV;
  camera.width = 640;
  camera.height = 480;
  camera.params = {520.0, 518.0, 322.5, 241.0, -0.12, 0.05, 0.001, -0.0005};
  return camera;
}

TEST(DetectChessboard, FindsRenderedCornersToATenthOfAPixel) {
  const CalibrationBoard board = ParseBoard("chessboard:9x6:0.03");
  const Camera camera = DistortedCamera();
  const std::vector<Rigid3d> poses =
      sim::RandomBoardPoses(camera, board, 8, 0.45, 0.9, 40.0, 7);
  sim::BoardImageOptions options;
  options.noise_sigma = 2.0;
  double sum_squares = 0.0;
  double worst = 0.0;
  int count = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const sim::BoardImage shot =
        sim::RenderBoardImage(camera, poses[i], board, options, 100 + i);
    ASSERT_TRUE(shot.all_corners_inside);
    const BoardObservation found =
        DetectChessboard(shot.image, board, "board" + std::to_string(i));
    ASSERT_TRUE(found.Found()) << "pose " << i;
    for (int k = 0; k < board.NumCorners(); ++k) {
      const double error = (found.pixels[k] - shot.corners[k]).norm();
      sum_squares += error * error;
      worst = std::max(worst, error);
      ++count;
    }
  }
  const double rms = std::sqrt(sum_squares / count);
  std::printf(
      "[ figures ] %d corners, 2 levels of noise: RMS %.4f px, worst "
      "%.4f px\n",
      count, rms, worst);
  EXPECT_LT(rms, 0.1);
  EXPECT_LT(worst, 0.3);
}

// mrgingham, mrcal's own chessboard finder (Debian's), on the same
// renders of a square board (the only kind it finds): both against the
// truth, and corner by corner against each other (the same numbering).
TEST(DetectChessboard, ComparedWithMrgingham) {
  const fs::path dir = testing::FreshTestDir("uw_chessboard_detector_test");
  const CalibrationBoard board = ParseBoard("chessboard:10x10:0.025");
  const Camera camera = DistortedCamera();
  const std::vector<Rigid3d> poses =
      sim::RandomBoardPoses(camera, board, 8, 0.4, 0.8, 40.0, 17);
  sim::BoardImageOptions options;
  options.noise_sigma = 2.0;
  std::vector<sim::BoardImage> shots;
  std::vector<BoardObservation> ours;
  for (size_t i = 0; i < poses.size(); ++i) {
    shots.push_back(
        sim::RenderBoardImage(camera, poses[i], board, options, 300 + i));
    const std::string name = "board" + std::to_string(i) + ".png";
    ASSERT_TRUE(cv::imwrite((dir / name).string(), shots.back().image));
    ours.push_back(DetectChessboard(shots.back().image, board, name));
  }
  const ProcessResult run = RunProcess(
      "cd " + testing::Quoted(dir) + " && mrgingham --gridn 10 '*.png'", false);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const CornersVnl theirs = ParseCornersVnl(run.output, "mrgingham", 100);
  double ours_squares = 0.0;
  double theirs_squares = 0.0;
  double between_worst = 0.0;
  int count = 0;
  for (const BoardObservation& found : theirs.observations) {
    const size_t i = std::stoul(found.image.substr(5));
    ASSERT_LT(i, shots.size()) << found.image;
    ASSERT_TRUE(found.Found()) << found.image;
    ASSERT_TRUE(ours[i].Found()) << found.image;
    for (int k = 0; k < board.NumCorners(); ++k) {
      ours_squares += (ours[i].pixels[k] - shots[i].corners[k]).squaredNorm();
      theirs_squares += (found.pixels[k] - shots[i].corners[k]).squaredNorm();
      between_worst =
          std::max(between_worst, (ours[i].pixels[k] - found.pixels[k]).norm());
      ++count;
    }
  }
  const double ours_rms = std::sqrt(ours_squares / count);
  const double theirs_rms = std::sqrt(theirs_squares / count);
  std::printf(
      "[ figures ] 10x10 board, %zu of %zu views found by mrgingham: RMS "
      "vs truth ours %.4f px, mrgingham %.4f px; corner by corner at most "
      "%.3f px apart\n",
      theirs.observations.size(), shots.size(), ours_rms, theirs_rms,
      between_worst);
  EXPECT_GE(theirs.observations.size(), 6u);
  EXPECT_LT(ours_rms, theirs_rms);
  EXPECT_LT(between_worst, 1.0);  // the same corners, numbered alike
}

// OpenCV's stereo sample (13 pairs of a 9x6 board, held upright in some):
// every board is found, and the two views of a pair number the same
// physical corners alike, which a rig calibration needs.
TEST(DetectChessboard, NumbersBothViewsOfRealStereoPairsAlike) {
  const fs::path dir =
      fs::path(UW_REALDATA_DIR) / "opencv_chessboard_stereo_640x480";
  ASSERT_TRUE(fs::is_directory(dir))
      << dir << " is missing: the tests read ../shared/realdata";
  const CalibrationBoard board = ParseBoard("chessboard:9x6:1");
  int found = 0;
  for (int n = 1; n <= 14; ++n) {
    if (n == 10) continue;  // not in OpenCV's sample
    std::vector<BoardObservation> pair;
    for (const char* side : {"left", "right"}) {
      char name[32];
      std::snprintf(name, sizeof(name), "%s%02d.jpg", side, n);
      const cv::Mat image = cv::imread((dir / name).string());
      ASSERT_FALSE(image.empty()) << name;
      pair.push_back(DetectChessboard(image, board, name));
      found += pair.back().Found();
    }
    if (!pair[0].Found() || !pair[1].Found()) continue;
    // Same numbering: the displacement of corner k from the left view to
    // the right one is nearly the same for every k (a disparity that varies
    // slowly over the board); under the half-turned numbering it spreads
    // over the board's size.
    auto spread = [&](bool half_turn) {
      std::vector<Eigen::Vector2d> shifts;
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for (int k = 0; k < board.NumCorners(); ++k) {
        const int r = half_turn ? board.NumCorners() - 1 - k : k;
        shifts.push_back(pair[1].pixels[r] - pair[0].pixels[k]);
        mean += shifts.back() / board.NumCorners();
      }
      double sum_squares = 0.0;
      for (const Eigen::Vector2d& shift : shifts) {
        sum_squares += (shift - mean).squaredNorm();
      }
      return std::sqrt(sum_squares / board.NumCorners());
    };
    const double same = spread(false);
    const double turned = spread(true);
    EXPECT_LT(same, 0.5 * turned) << "pair " << n;
    const Eigen::Vector2d along_row = pair[0].pixels[8] - pair[0].pixels[0];
    EXPECT_GT(along_row.x() + along_row.y(), 0.0) << "pair " << n;
  }
  EXPECT_EQ(found, 26);
}

TEST(DetectChessboard, NoBoardAndBadImages) {
  const CalibrationBoard board = ParseBoard("chessboard:9x6:0.03");
  const cv::Mat flat(480, 640, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(DetectChessboard(flat, board, "flat.png").Found());
  EXPECT_THROW(DetectChessboard(cv::Mat(), board, "empty.png"), Error);
  EXPECT_THROW(DetectChessboard(cv::Mat(10, 10, CV_16UC1), board, "x.png"),
               Error);
}

}  // namespace
}  // namespace uw
