#include "calib/apriltag_detector.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "common/util/error.h"

namespace uw {
namespace {

namespace fs = std::filesystem;
const fs::path kRealData(UW_REALDATA_DIR);

// The AprilTag project's reference detections: "id, (x y), (x y), (x y),
// (x y)" a tag, libapriltag's corner order and pixel convention.
std::vector<AprilTagDetection> ReadReference(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::vector<AprilTagDetection> tags;
  const std::regex number("-?[0-9]+(\\.[0-9]+)?");
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> values;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), number);
         it != std::sregex_iterator(); ++it) {
      values.push_back(std::stod(it->str()));
    }
    if (values.size() != 9) continue;
    AprilTagDetection tag;
    tag.id = static_cast<int>(values[0]);
    for (int k = 0; k < 4; ++k) {
      // To mrcal's convention, as DetectAprilTags gives them.
      tag.corners[k] =
          Eigen::Vector2d(values[1 + 2 * k] - 0.5, values[2 + 2 * k] - 0.5);
    }
    tags.push_back(tag);
  }
  return tags;
}

TEST(DetectAprilTags, FindsTheReferenceTagsToAHalfPixel) {
  const fs::path dir = kRealData / "apriltag_test_images";
  ASSERT_TRUE(fs::is_directory(dir))
      << dir << " is missing: the tests read ../shared/realdata";
  int total = 0;
  double worst = 0.0;
  for (const char* name :
       {"33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c",
        "34139872896_defdb2f8d9_c"}) {
    const std::vector<AprilTagDetection> reference =
        ReadReference(dir / (std::string(name) + ".txt"));
    const cv::Mat image = cv::imread(
        (dir / (std::string(name) + ".jpg")).string(), cv::IMREAD_GRAYSCALE);
    const std::vector<AprilTagDetection> found =
        DetectAprilTags(image, AprilTagOptions());
    EXPECT_EQ(found.size(), reference.size()) << name;
    // Each reference tag against the detection with the nearest first
    // corner (these images hold many tags of one id).
    for (const AprilTagDetection& truth : reference) {
      const AprilTagDetection* nearest = nullptr;
      for (const AprilTagDetection& tag : found) {
        if (tag.id == truth.id &&
            (nearest == nullptr ||
             (tag.corners[0] - truth.corners[0]).norm() <
                 (nearest->corners[0] - truth.corners[0]).norm())) {
          nearest = &tag;
        }
      }
      ASSERT_NE(nearest, nullptr) << name;
      for (int k = 0; k < 4; ++k) {
        worst =
            std::max(worst, (nearest->corners[k] - truth.corners[k]).norm());
      }
    }
    total += static_cast<int>(reference.size());
  }
  std::printf(
      "[ figures ] %d reference tags; worst corner %.4f px from the "
      "reference\n",
      total, worst);
  EXPECT_EQ(total, 47);
  EXPECT_LT(worst, 0.5);
}

// Kalibr AprilGrids: tag36h11 codes inside a 2-cell black border.
TEST(DetectAprilTags, KalibrGridTagsNeedTheTwoCellBorder) {
  const fs::path dir =
      kRealData / "aprilgrid_samples" / "powei-lin_aprilgrid-rs_tests";
  AprilTagOptions kalibr;
  kalibr.border_cells = 2;
  kalibr.quad_decimate = 2.0;
  struct Case {
    const char* image;
    int expected;
  };
  for (const Case& c : {Case{"iphone.png", 66}, Case{"two_boards.png", 72}}) {
    const cv::Mat image =
        cv::imread((dir / c.image).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << c.image;
    const std::vector<AprilTagDetection> stock =
        DetectAprilTags(image, AprilTagOptions());
    const std::vector<AprilTagDetection> found = DetectAprilTags(image, kalibr);
    std::printf(
        "[ figures ] %s: %zu tags with the 2-cell border (expected "
        "%d), %zu with stock tag36h11\n",
        c.image, found.size(), c.expected, stock.size());
    EXPECT_EQ(static_cast<int>(found.size()), c.expected) << c.image;
    // Stock tag36h11 reads no grid tag; at most a stray false decode.
    EXPECT_LE(stock.size(), 2u) << c.image;
    for (size_t i = 0; i < found.size(); ++i) {
      EXPECT_EQ(found[i].id, static_cast<int>(i)) << c.image;
    }
  }
  // Dim fisheye frames (expected 36 each): what the detector alone finds;
  // the rest needs grid completion (not done yet).
  for (const char* name : {"EuRoC.png", "TUM_VI.png", "right.png", "r45.png",
                           "top.png", "top_right.png"}) {
    const cv::Mat image =
        cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << name;
    std::printf("[ figures ] %s: %zu of 36 tags\n", name,
                DetectAprilTags(image, kalibr).size());
  }
}

TEST(DetectAprilTags, BadOptionsAndImages) {
  AprilTagOptions options;
  options.family = "tag99h1";
  EXPECT_THROW(options.Check(), Error);
  options = AprilTagOptions();
  options.border_cells = 0;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_THROW(DetectAprilTags(cv::Mat(), AprilTagOptions()), Error);
  EXPECT_TRUE(DetectAprilTags(cv::Mat(100, 100, CV_8UC1, cv::Scalar(128)),
                              AprilTagOptions())
                  .empty());
}

}  // namespace
}  // namespace uw
