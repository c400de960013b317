#include "calib/board_detection.h"

#include <atomic>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error_testing.h"
#include "sim/board_images.h"
#include "tests/support/process.h"

namespace uw {
namespace {

namespace fs = std::filesystem;

Camera PinholeCamera() {
  Camera camera;
  camera.model_id = CameraModelId::kPinhole;
  camera.width = 640;
  camera.height = 480;
  camera.params = {520.0, 520.0, 320.0, 240.0};
  return camera;
}

// Three rendered views of a chessboard and a grey image without it.
std::vector<std::string> WriteSession(const CalibrationBoard& board,
                                      const fs::path& dir) {
  const Camera camera = PinholeCamera();
  const std::vector<Rigid3d> poses =
      sim::RandomBoardPoses(camera, board, 3, 0.5, 0.8, 20.0, 3);
  std::vector<std::string> names;
  for (size_t i = 0; i < poses.size(); ++i) {
    names.push_back("view" + std::to_string(i) + ".png");
    EXPECT_TRUE(cv::imwrite(
        (dir / names.back()).string(),
        sim::RenderBoardImage(camera, poses[i], board, {}, i).image));
  }
  names.insert(names.begin() + 1, "empty.png");
  EXPECT_TRUE(cv::imwrite((dir / "empty.png").string(),
                          cv::Mat(480, 640, CV_8UC1, cv::Scalar(128))));
  return names;
}

TEST(DetectBoardInImages, EveryImageInOrderWhateverTheThreads) {
  const fs::path dir = testing::FreshTestDir("uw_board_detection_test");
  const CalibrationBoard board = ParseBoard("chessboard:9x6:0.03");
  const std::vector<std::string> names = WriteSession(board, dir);
  std::atomic<int> calls{0};
  std::atomic<int> most_done{0};
  const std::vector<BoardObservation> one =
      DetectBoardInImages(dir.string(), names, board, 1, [&](int done, int) {
        ++calls;
        most_done = std::max(most_done.load(), done);
      });
  EXPECT_EQ(calls, 4);
  EXPECT_EQ(most_done, 4);
  ASSERT_EQ(one.size(), names.size());
  for (size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(one[i].image, names[i]);
    EXPECT_EQ(one[i].Found(), names[i] != "empty.png") << names[i];
  }
  const std::vector<BoardObservation> two =
      DetectBoardInImages(dir.string(), names, board, 2);
  ASSERT_EQ(two.size(), one.size());
  for (size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(two[i].pixels, one[i].pixels) << names[i];
  }
}

TEST(DetectBoardInImages, NamesWithWhiteSpaceAndUnreadableImagesAreRefused) {
  const fs::path dir = testing::FreshTestDir("uw_board_detection_test");
  const CalibrationBoard board = ParseBoard("chessboard:9x6:0.03");
  ExpectErrorContaining(
      [&] { DetectBoardInImages("calib", {"a b.png"}, board, 1); },
      "calib/a b.png: image names with white space cannot go into "
      "corners.vnl");
  ExpectErrorContaining(
      [&] { DetectBoardInImages(dir.string(), {"missing.png"}, board, 1); },
      "missing.png: cannot read the image");
}

}  // namespace
}  // namespace uw
